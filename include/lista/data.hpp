// Typed, type-erased values that flow through stage ports. Every port type has
// one name used in code, TOML checks, docs and `--describe`:
//   missions     lista::MissionSet
//   points       lista::MissionPoints   (per-mission change points, common frame)
//   objects      lista::ObjectSet
//   descriptors  lista::DescriptorSet
//   groups       lista::Groups
//   matches      lista::Matches
// Values are immutable once published and shared between consumers, so
// independent stages may read them in parallel.
#pragma once

#include <lista/descriptors.hpp>
#include <lista/error.hpp>
#include <lista/groups.hpp>
#include <lista/matches.hpp>
#include <lista/missions.hpp>
#include <lista/objects.hpp>

#include <map>
#include <memory>
#include <string>

namespace lista {

template <class T>
struct PortTraits;  // specialised below; `name` is the port type name
template <> struct PortTraits<MissionSet> { static constexpr const char* name = "missions"; };
template <> struct PortTraits<MissionPoints> { static constexpr const char* name = "points"; };
template <> struct PortTraits<ObjectSet> { static constexpr const char* name = "objects"; };
template <> struct PortTraits<DescriptorSet> { static constexpr const char* name = "descriptors"; };
template <> struct PortTraits<Groups> { static constexpr const char* name = "groups"; };
template <> struct PortTraits<Matches> { static constexpr const char* name = "matches"; };

// All port type names, for validation and docs.
const std::vector<std::string>& port_types();

class Data {
 public:
  Data() = default;
  template <class T>
  static Data make(T value) {
    return Data(std::make_shared<const T>(std::move(value)), PortTraits<T>::name);
  }
  template <class T>
  static Data share(std::shared_ptr<const T> value) {
    return Data(std::move(value), PortTraits<T>::name);
  }
  // The value as T; throws lista::Error when the held type is another one.
  template <class T>
  const T& as() const { return *shared<T>(); }
  template <class T>
  std::shared_ptr<const T> shared() const {
    if (!ptr_ || type_ != PortTraits<T>::name)
      throw Error("port value is '" + (ptr_ ? type_ : std::string("empty")) +
                  "', expected '" + PortTraits<T>::name + "'");
    return std::static_pointer_cast<const T>(ptr_);
  }
  const std::string& type() const { return type_; }
  explicit operator bool() const { return static_cast<bool>(ptr_); }

 private:
  Data(std::shared_ptr<const void> p, std::string type) : ptr_(std::move(p)), type_(std::move(type)) {}
  std::shared_ptr<const void> ptr_;
  std::string type_;
};

// What a stage receives: one value per connected input port.
class Inputs {
 public:
  bool has(const std::string& port) const { return values_.count(port) != 0; }
  template <class T>
  const T& get(const std::string& port) const { return at(port).as<T>(); }
  template <class T>
  std::shared_ptr<const T> shared(const std::string& port) const { return at(port).shared<T>(); }
  const Data& at(const std::string& port) const;  // throws lista::Error if not connected
  void set(const std::string& port, Data value) { values_[port] = std::move(value); }
  const std::map<std::string, Data>& values() const { return values_; }

 private:
  std::map<std::string, Data> values_;
};

// What a stage produces: one value per output port it declares.
class Outputs {
 public:
  template <class T>
  void put(const std::string& port, T value) { values_[port] = Data::make<T>(std::move(value)); }
  void put(const std::string& port, Data value) { values_[port] = std::move(value); }
  // A stage's only output: return Outputs::of("changes", std::move(out));
  template <class T>
  static Outputs of(const std::string& port, T value) {
    Outputs o;
    o.put(port, std::move(value));
    return o;
  }
  bool has(const std::string& port) const { return values_.count(port) != 0; }
  const Data& at(const std::string& port) const;
  const std::map<std::string, Data>& values() const { return values_; }

 private:
  std::map<std::string, Data> values_;
};

}  // namespace lista
