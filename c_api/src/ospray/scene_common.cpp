// The scene objects' shared parameter reading.
#include "scene_common.hpp"

#include <algorithm>

namespace sciray::ospray {

namespace {

/// A one-element array holding the single value (or object) of `p`, of element type `type`.
Ref<Object> one_element_array(const Param& p, OSPDataType type) {
  const Object* handle = p.object.get();
  const void* value = is_object_type(type) ? static_cast<const void*>(&handle) : p.bytes.data();
  const Data view(value, type, {1, 1, 1}, {0, 0, 0}, nullptr, nullptr);
  Ref<Object> array(new Data(type, {1, 1, 1}));
  array->release();  // the Ref holds the only reference
  static_cast<Data&>(*array).copy_from(view, {0, 0, 0});
  return array;
}

}  // namespace

const Data* get_data(const Object& owner, const Param* p, const std::string& id,
                     std::initializer_list<OSPDataType> accepted) {
  if (!p || (!p->object && is_object_type(p->type))) return nullptr;  // absent, or set to NULL
  const auto accepts = [&](OSPDataType t) { return std::find(accepted.begin(), accepted.end(), t) != accepted.end(); };
  std::string expected;
  for (auto t : accepted) expected += (expected.empty() ? "" : " or ") + type_name(t);
  const Data* data = nullptr;
  if (p->object && p->object->kind() == OSP_DATA) {
    data = static_cast<const Data*>(p->object.get());
  } else {
    // OSPRay's convention: a single value where an array is expected is a one-element array.
    const OSPDataType type = p->object ? p->object->kind() : p->type;
    if (!accepts(type))
      throw Error(owner.name() + ": parameter '" + id + "' must be an OSPData array of " + expected + " (or one " +
                  expected + "), got " + type_name(type));
    if (!p->as_array) p->as_array = one_element_array(*p, type);
    data = static_cast<const Data*>(p->as_array.get());
  }
  if (!accepts(data->element_type()))
    throw Error(owner.name() + ": parameter '" + id + "' must be an array of " + expected + ", got an array of " +
                type_name(data->element_type()));
  if (data->dimensions() != 1) throw Error(owner.name() + ": parameter '" + id + "' must be a 1D array");
  return data;
}

std::size_t per_item_count(const Object& owner, const std::string& id, const Data& data, std::size_t items,
                           const char* item_name, bool broadcast) {
  if (broadcast && data.size() == 1) return 1;
  if (data.size() < items)
    throw Error(owner.name() + ": parameter '" + id + "' has " + std::to_string(data.size()) + " elements but there are " +
                std::to_string(items) + " " + item_name + (broadcast ? " (give one for all, or one for each)" : ""));
  return items;
}

void append_per_item(PaddedVector<float>& out, const Object& owner, const std::string& id, const Data& data,
                     std::size_t items, const char* item_name, bool broadcast, int components, int pad_to) {
  const std::size_t given = per_item_count(owner, id, data, items, item_name, broadcast);
  pad_to = std::max(pad_to, components);
  out.reserve(out.size() + static_cast<std::size_t>(pad_to) * items);
  for (std::size_t i = 0; i < items; ++i) {
    const std::byte* e = data.element(given == 1 ? 0 : i);
    for (int c = 0; c < components; ++c) out.push_back(read_float(e + 4 * c));
    for (int c = components; c < pad_to; ++c) out.push_back(1.f);
  }
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
