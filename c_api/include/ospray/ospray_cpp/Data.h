// sciray's OSPRay C++ wrapper: data arrays. Data<SHARED> makes an OSPData from application
// memory, inferring the element type with OSPTypeFor: SharedData (Data<true>) references
// the memory, which must outlive the array's use; CopiedData (Data<false>) copies it at
// construction; MovedData takes a std::vector over and frees it when OSPRay lets go.
// Dimensions are an int, a size_t or a 2- or 3-vector of them (OSP_INT, OSP_ULONG,
// OSP_VEC2I/3I, OSP_VEC2UL/3UL); byte strides, of the same type, are 0 for packed elements.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

template <bool SHARED = false>
class Data : public ManagedObject<OSPData, OSP_DATA> {
public:
  // Elements of an explicit type.
  template <typename DIM_T>
  Data(const void* init, OSPDataType elementType, const DIM_T& numItems) {
    make(init, elementType, numItems, static_cast<const DIM_T*>(nullptr));
  }
  template <typename DIM_T>
  Data(const void* init, OSPDataType elementType, const DIM_T& numItems, const DIM_T& byteStride) {
    make(init, elementType, numItems, &byteStride);
  }

  // Elements whose type is inferred from the pointer.
  template <typename T, typename DIM_T>
  Data(const T* init, const DIM_T& numItems) {
    requireElementType<T>();
    make(init, OSPTypeFor<T>::value, numItems, static_cast<const DIM_T*>(nullptr));
  }
  template <typename T, typename DIM_T>
  Data(const T* init, const DIM_T& numItems, const DIM_T& byteStride) {
    requireElementType<T>();
    make(init, OSPTypeFor<T>::value, numItems, &byteStride);
  }

  template <typename T, std::size_t N>
  Data(const std::array<T, N>& items) : Data(items.data(), N) {}
  template <typename T, typename ALLOC_T>
  Data(const std::vector<T, ALLOC_T>& items) : Data(items.data(), items.size()) {}

  // A one-element array of `item` (an object wrapper, a handle, a value).
  template <typename T>
  Data(const T& item) : Data(&item, std::size_t(1)) {}

  // Adopts an existing array handle.
  Data(OSPData existing = nullptr) : ManagedObject(existing) {}

protected:
  template <typename T>
  static void requireElementType() {
    static_assert(OSPTypeFor<T>::value != OSP_UNKNOWN,
                  "Data: this element type has no OSPDataType; vector, box and matrix types need an "
                  "OSPTypeFor specialization (include ospray/ospray_cpp/ext/glm.h or ext/rkcommon.h, "
                  "or use OSPTYPEFOR_SPECIALIZATION)");
  }

private:
  // Without `byteStride` (NULL) the elements are packed.
  template <typename DIM_T>
  void make(const void* init, OSPDataType elementType, const DIM_T& numItems, const DIM_T* byteStride) {
    constexpr OSPDataType dimType = OSPTypeFor<DIM_T>::value;
    static_assert(dimType == OSP_INT || dimType == OSP_VEC2I || dimType == OSP_VEC3I || dimType == OSP_ULONG ||
                      dimType == OSP_VEC2UL || dimType == OSP_VEC3UL,
                  "Data: dimensions and strides must be an int, a size_t or a 2- or 3-vector of them "
                  "(OSP_INT, OSP_ULONG, OSP_VEC2I, OSP_VEC3I, OSP_VEC2UL, OSP_VEC3UL)");
    using Component = typename OSPVecElementOf<dimType>::type;
    constexpr std::size_t dims = OSPDimensionalityOf<dimType>::value;
    static_assert(sizeof(DIM_T) == sizeof(Component[dims]), "Data: a dimension vector is its components, packed");

    Component items[dims], strides[dims] = {};
    std::memcpy(items, &numItems, sizeof(items));
    if (byteStride) std::memcpy(strides, byteStride, sizeof(strides));
    std::uint64_t n[3] = {1, 1, 1};
    std::int64_t stride[3] = {0, 0, 0};
    for (std::size_t d = 0; d < dims; ++d) {
      n[d] = static_cast<std::uint64_t>(items[d]);
      stride[d] = static_cast<std::int64_t>(strides[d]);
    }

    OSPData shared = ospNewSharedData(init, elementType, n[0], stride[0], n[1], stride[1], n[2], stride[2]);
    if (SHARED) {
      ospObject = shared;
      return;
    }
    // A copy is an array of its own, filled from a temporary view of the caller's memory.
    ospObject = ospNewData(elementType, n[0], n[1], n[2]);
    if (shared && ospObject) ospCopyData(shared, ospObject);
    ospRelease(shared);
  }
};

using SharedData = Data<true>;
using CopiedData = Data<false>;

// Takes the vector's elements over (`items` is left empty); OSPRay frees them when the last
// holder of the array lets go, without a copy.
class MovedData : public SharedData {
public:
  template <typename T, typename ALLOC_T>
  MovedData(std::vector<T, ALLOC_T>& items) {
    requireElementType<T>();
    auto* owned = new std::vector<T, ALLOC_T>(std::move(items));
    ospObject = ospNewSharedData(owned->data(), OSPTypeFor<T>::value, owned->size(), 0, 1, 0, 1, 0,
                                 &deleteVector<T, ALLOC_T>, owned);
    if (!ospObject) delete owned;  // a refused array never calls its deleter
  }

private:
  template <typename T, typename ALLOC_T>
  static void deleteVector(const void* vector, const void* /*elements*/) {
    delete static_cast<const std::vector<T, ALLOC_T>*>(vector);
  }
};

SCIRAY_OSP_CPP_CHECK_LAYOUT(SharedData, OSPData);
SCIRAY_OSP_CPP_CHECK_LAYOUT(CopiedData, OSPData);
SCIRAY_OSP_CPP_CHECK_LAYOUT(MovedData, OSPData);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::SharedData, OSP_DATA)
OSPTYPEFOR_SPECIALIZATION(cpp::CopiedData, OSP_DATA)
OSPTYPEFOR_SPECIALIZATION(cpp::MovedData, OSP_DATA)

}  // namespace ospray
