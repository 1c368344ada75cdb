// sciray's OSPRay C++ wrapper: TransferFunction, made by type name or adopting an existing OSPTransferFunction.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class TransferFunction : public ManagedObject<OSPTransferFunction, OSP_TRANSFER_FUNCTION> {
public:
  TransferFunction(const std::string& typeName) : ManagedObject(ospNewTransferFunction(typeName.c_str())) {}
  TransferFunction(OSPTransferFunction existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(TransferFunction, OSPTransferFunction);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::TransferFunction, OSP_TRANSFER_FUNCTION)

}  // namespace ospray
