#include "data.hpp"

namespace sciray::ospray {

namespace {
std::array<std::int64_t, 3> compact_strides(OSPDataType type, const std::array<std::uint64_t, 3>& counts,
                                            std::array<std::int64_t, 3> strides) {
  const auto element = static_cast<std::int64_t>(size_of(type));
  if (strides[0] == 0) strides[0] = element;
  if (strides[1] == 0) strides[1] = strides[0] * static_cast<std::int64_t>(counts[0]);
  if (strides[2] == 0) strides[2] = strides[1] * static_cast<std::int64_t>(counts[1]);
  return strides;
}
void check_counts(OSPDataType type, const std::array<std::uint64_t, 3>& counts) {
  if (type == OSP_STRING || size_of(type) == 0)
    throw Error("data: element type " + type_name(type) + " cannot be stored in a data array");
  for (auto n : counts)
    if (n == 0) throw Error("data: every dimension must hold at least one item");
}
}  // namespace

Data::Data(const void* shared, OSPDataType type, std::array<std::uint64_t, 3> counts,
           std::array<std::int64_t, 3> strides, OSPDeleterCallback deleter, const void* deleter_user_data)
    : Object(OSP_DATA, ""), element_type_(type), counts_(counts), deleter_(deleter),
      deleter_user_data_(deleter_user_data), shared_(shared) {
  if (!shared) throw Error("data: the shared memory pointer is NULL");
  check_counts(type, counts);
  strides_ = compact_strides(type, counts, strides);
  base_ = static_cast<const std::byte*>(shared);
  retain_objects();
}

Data::Data(OSPDataType type, std::array<std::uint64_t, 3> counts) : Object(OSP_DATA, ""), element_type_(type), counts_(counts) {
  check_counts(type, counts);
  strides_ = compact_strides(type, counts, {0, 0, 0});
  owned_.assign(size() * size_of(type), std::byte{0});
  base_ = owned_.data();
  if (is_object_type(type)) objects_.resize(size());
}

Data::~Data() {
  if (deleter_) deleter_(deleter_user_data_, shared_);
}

void Data::for_each_reference(const std::function<void(const Object&)>& visit) const {
  Object::for_each_reference(visit);
  for (const Ref<Object>& o : objects_)
    if (o) visit(*o);
}

void Data::retain_objects() {
  if (!is_object_type(element_type_)) return;
  objects_.reserve(size());
  for (std::uint64_t k = 0; k < counts_[2]; ++k)
    for (std::uint64_t j = 0; j < counts_[1]; ++j)
      for (std::uint64_t i = 0; i < counts_[0]; ++i) {
        Object* handle;
        std::memcpy(&handle, element(i, j, k), sizeof(handle));
        if (handle && !Registry::instance().alive(handle))
          throw Error("data: element " + std::to_string(objects_.size()) + " is an invalid or released handle");
        if (handle && element_type_ != OSP_OBJECT && handle->kind() != element_type_)
          throw Error("data: element " + std::to_string(objects_.size()) + " is " + type_name(handle->kind()) +
                      " but the array holds " + type_name(element_type_));
        objects_.emplace_back(handle);
      }
}

void Data::copy_from(const Data& source, std::array<std::uint64_t, 3> offset) {
  if (owned_.empty()) throw Error("data: ospCopyData needs a destination made by ospNewData, not shared data");
  if (source.element_type_ != element_type_)
    throw Error("data: ospCopyData from " + type_name(source.element_type_) + " into " + type_name(element_type_));
  for (int d = 0; d < 3; ++d)
    if (offset[d] + source.counts_[d] > counts_[d])
      throw Error("data: ospCopyData of " + std::to_string(source.counts_[d]) + " items at index " +
                  std::to_string(offset[d]) + " overflows dimension " + std::to_string(d + 1) + " of size " +
                  std::to_string(counts_[d]));
  std::vector<const Object*> copied;
  for (const Ref<Object>& o : source.objects_)
    if (o) copied.push_back(o.get());
  if (const Object* o = first_referring_to(copied, *this))
    throw Error("data: ospCopyData would put into this array " + o->name() +
                ", which refers to the array: a cycle of references, never released");
  const std::size_t bytes = size_of(element_type_);
  for (std::uint64_t k = 0; k < source.counts_[2]; ++k)
    for (std::uint64_t j = 0; j < source.counts_[1]; ++j)
      for (std::uint64_t i = 0; i < source.counts_[0]; ++i) {
        std::byte* to = const_cast<std::byte*>(element(offset[0] + i, offset[1] + j, offset[2] + k));
        if (objects_.empty()) {
          std::memcpy(to, source.element(i, j, k), bytes);
        } else {
          // The source's objects as it checked and retained them: a shared source's memory
          // may hold other bytes by now.
          Object* handle = source.object(i + source.counts_[0] * (j + source.counts_[1] * k));
          std::memcpy(to, &handle, sizeof(handle));
          objects_[(offset[0] + i) + counts_[0] * ((offset[1] + j) + counts_[1] * (offset[2] + k))] = handle;
        }
      }
}

}  // namespace sciray::ospray
