// The scene objects' shared parameter reading.
#include "scene_common.hpp"

#include <algorithm>

namespace sciray::ospray {

const Data* get_data(const Object& owner, const Param* p, const std::string& id,
                     std::initializer_list<OSPDataType> accepted) {
  if (!p || (!p->object && is_object_type(p->type))) return nullptr;  // absent, or set to NULL
  if (!p->object || p->object->kind() != OSP_DATA)
    throw Error(owner.name() + ": parameter '" + id + "' must be an OSPData array, got " +
                type_name(p->object ? p->object->kind() : p->type));
  const auto* data = static_cast<const Data*>(p->object.get());
  if (std::find(accepted.begin(), accepted.end(), data->element_type()) == accepted.end()) {
    std::string expected;
    for (auto t : accepted) expected += (expected.empty() ? "" : " or ") + type_name(t);
    throw Error(owner.name() + ": parameter '" + id + "' must be an array of " + expected + ", got an array of " +
                type_name(data->element_type()));
  }
  if (data->dimensions() != 1) throw Error(owner.name() + ": parameter '" + id + "' must be a 1D array");
  return data;
}

void append_floats(PaddedVector<float>& out, const Data& data, int components, int pad_to) {
  pad_to = std::max(pad_to, components);
  out.reserve(out.size() + static_cast<std::size_t>(pad_to) * data.size());
  for (std::uint64_t i = 0; i < data.size(); ++i) {
    for (int c = 0; c < components; ++c) out.push_back(read_float(data.element(i) + 4 * c));
    for (int c = components; c < pad_to; ++c) out.push_back(1.f);
  }
}

int get_enum(const Object& owner, int value, const char* id, std::initializer_list<const char*> names, int first) {
  if (value >= first && value - first < static_cast<int>(names.size())) return value - first;
  std::string known;
  int i = 0;
  for (const char* n : names) known += (i ? ", " : "") + std::string(n) + " = " + std::to_string(first + i), ++i;
  throw Error(owner.name() + ": parameter '" + id + "' has unknown value " + std::to_string(value) + " (" + known +
              ")");
}

}  // namespace sciray::ospray
