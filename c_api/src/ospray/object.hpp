#pragma once
// The OSPRay object model over sciray: reference-counted objects with named, typed
// parameters that become visible at commit. Every handle the C API returns is an
// Object*; the registry tells live handles from released or foreign pointers.
#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <type_traits>
#include <unordered_set>
#include <vector>

#include <ospray/ospray.h>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"

namespace sciray::ospray {

class Object;

/// Bytes one value of `type` occupies (0 for types that are not plain values).
std::size_t size_of(OSPDataType type);
/// OSPRay's name of a type, for messages ("vec3f", "OSPGeometry").
std::string type_name(OSPDataType type);
inline bool is_object_type(OSPDataType type) { return (type & OSP_OBJECT) == OSP_OBJECT; }

/// All live objects; handles are checked against it on every API call.
class Registry {
public:
  static Registry& instance() {
    static Registry registry;
    return registry;
  }
  void add(Object* o) {
    std::lock_guard lock(mutex_);
    live_.insert(o);
  }
  void remove(Object* o) {
    std::lock_guard lock(mutex_);
    live_.erase(o);
  }
  bool alive(const void* o) const {
    std::lock_guard lock(mutex_);
    return live_.count(static_cast<Object*>(const_cast<void*>(o))) != 0;
  }
  std::size_t count() const {
    std::lock_guard lock(mutex_);
    return live_.size();
  }

private:
  mutable std::mutex mutex_;
  std::unordered_set<Object*> live_;
};

/// An owning reference (retains on copy, releases on destruction).
template <class T>
class Ref {
public:
  Ref() = default;
  Ref(T* p) : p_(p) {  // NOLINT: implicit from raw pointers, as handles arrive
    if (p_) p_->retain();
  }
  Ref(const Ref& o) : Ref(o.p_) {}
  Ref(Ref&& o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
  Ref& operator=(Ref o) noexcept {
    std::swap(p_, o.p_);
    return *this;
  }
  ~Ref() {
    if (p_) p_->release();
  }
  T* get() const { return p_; }
  T* operator->() const { return p_; }
  T& operator*() const { return *p_; }
  explicit operator bool() const { return p_ != nullptr; }

private:
  T* p_ = nullptr;
};

/// One parameter value: plain bytes, a string, or an object reference.
struct Param {
  OSPDataType type = OSP_UNKNOWN;
  std::vector<std::byte> bytes;
  std::string string;
  Ref<Object> object;
  mutable bool used = false;
  /// The one-element array a single value stands for where an array is expected (made
  /// on first such read; see get_data).
  mutable Ref<Object> as_array;
};

/// The first of `from` that is `target` or reaches it through references, or null: a
/// reference from `target` to it would make a cycle, whose objects would never be released.
/// One walk for all of `from`, however much of the graph they share.
const Object* first_referring_to(std::span<const Object* const> from, const Object& target);
inline bool refers_to(const Object& from, const Object& target) {
  const Object* start = &from;
  return first_referring_to({&start, 1}, target) != nullptr;
}

class Object {
public:
  Object(OSPDataType kind, std::string subtype) : kind_(kind), subtype_(std::move(subtype)) {
    Registry::instance().add(this);
  }
  virtual ~Object() { Registry::instance().remove(this); }
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;

  void retain() { refs_.fetch_add(1, std::memory_order_relaxed); }
  void release() {
    if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
  }
  int ref_count() const { return refs_.load(); }

  OSPDataType kind() const { return kind_; }
  const std::string& subtype() const { return subtype_; }
  /// "mesh geometry", "perspective camera": how messages name this object.
  std::string name() const;

  void set_param(const std::string& id, OSPDataType type, const void* mem);
  void remove_param(const std::string& id) { staged_.erase(id); }

  /// Makes the staged parameters visible and rebuilds the object's state from them.
  /// Returns the names of parameters the object did not read (OSPRay warns about them).
  std::vector<std::string> commit();
  /// What the last commit reported at OSPRay's debug level (parameters OSPRay ignores
  /// without a warning), to be passed on as status messages.
  const std::vector<std::string>& debug_messages() const { return debug_messages_; }

  /// Calls `visit` with every object this one holds a reference to through its
  /// parameters, staged or committed (and, for arrays, through its elements).
  virtual void for_each_reference(const std::function<void(const Object&)>& visit) const;

  /// Monotonic stamp of the last successful commit of this object or anything it uses.
  virtual std::uint64_t version() const { return version_; }
  bool committed() const { return version_ != 0; }

protected:
  /// Reads committed parameters; throws Error naming the bad one.
  virtual void on_commit() {}

  // Committed-parameter access; each marks the parameter as used.
  const Param* find(const std::string& id) const;
  bool has(const std::string& id) const { return find(id) != nullptr; }
  float get_float(const std::string& id, float fallback) const;
  int get_int(const std::string& id, int fallback) const;
  bool get_bool(const std::string& id, bool fallback) const;
  /// OSPRay 3's `id` of models and instances: what the id channels show in place of the
  /// object's index; empty where unset or 0xFFFFFFFF (OSPRay's "none"). Read as OSPRay
  /// reads it, a uint only: another type is an error, as OSPRay would ignore it.
  std::optional<std::uint32_t> get_user_id() const;
  Vec3f get_vec3f(const std::string& id, Vec3f fallback) const;
  /// Reads a float, bool or vec3f parameter into `field`, which keeps its value where the
  /// parameter is unset (an optional vec3f stays empty).
  template <class T>
  void read_into(const std::string& id, T& field) const {
    if constexpr (std::is_same_v<T, float>)
      field = get_float(id, field);
    else if constexpr (std::is_same_v<T, bool>)
      field = get_bool(id, field);
    else if constexpr (std::is_same_v<T, std::optional<Vec3f>>)
      field = has(id) ? std::optional<Vec3f>(get_vec3f(id, {})) : field;
    else
      field = get_vec3f(id, field);
  }
  /// A vec4f that OSPRay also accepts as a vec3f (alpha 0) or a float (grey, alpha 0).
  std::array<float, 4> get_color4(const std::string& id, std::array<float, 4> fallback) const;
  template <class T>
  T* get_object(const std::string& id, OSPDataType kind, bool required) const;

  std::uint64_t version_ = 0;
  void debug_message(std::string message) { debug_messages_.push_back(std::move(message)); }

private:
  static std::uint64_t next_version() {
    static std::atomic<std::uint64_t> counter{0};
    return ++counter;
  }

  OSPDataType kind_;
  std::string subtype_;
  std::atomic<int> refs_{1};
  std::map<std::string, Param> staged_;
  std::map<std::string, Param> committed_;
  std::vector<std::string> debug_messages_;
};

}  // namespace sciray::ospray

namespace sciray::ospray {

template <class T>
T* Object::get_object(const std::string& id, OSPDataType kind, bool required) const {
  const Param* p = find(id);
  if (!p || !p->object) {
    if (required) throw Error(name() + ": required parameter '" + id + "' (" + type_name(kind) + ") is missing");
    return nullptr;
  }
  if (p->object->kind() != kind)
    throw Error(name() + ": parameter '" + id + "' must be " + type_name(kind) + ", got " +
                type_name(p->object->kind()));
  return static_cast<T*>(p->object.get());
}

}  // namespace sciray::ospray
