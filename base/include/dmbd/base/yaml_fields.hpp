#pragma once
// Reading a map of settings with the located reader (yaml_reader.hpp): the helpers every
// settings reader shares (a scenario's sections, a bus controller's options, a robot
// folder's files). Each records its problem in the Reader and throws Skip, as the
// Reader's own value functions do; optional() and each() catch it, so that one mistake
// loses only its own value and reading goes on.
#include <array>
#include <initializer_list>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "dmbd/base/yaml_reader.hpp"

namespace dmbd::yaml {

class Fields {
 public:
  explicit Fields(Reader& rd) : rd_(rd) {}
  Reader& reader() const { return rd_; }
  std::string at(const YAML::Node& n) const { return rd_.at(n).str(); }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const { rd_.fail(n, what); }

  // f(map[key]) when the map has the key; its problems recorded and reading going on.
  template <class F>
  void optional(const YAML::Node& map, const char* key, F&& f) const {
    if (const YAML::Node v = map[key]) rd_.guard([&] { f(v); });
  }
  // f(e) for each entry of a list, each one's problems recorded apart.
  template <class F>
  void each(const YAML::Node& list, F&& f) const {
    for (const auto& e : list) rd_.guard([&] { f(e); });
  }
  // The value of a key the map n must have.
  YAML::Node required(const YAML::Node& n, const char* key, const std::string& what) const;
  // A map with an unknown key is not read further (Skip): its missing keys may be misspelt ones.
  void keys(const YAML::Node& n, const std::string& what, std::initializer_list<const char*> allowed) const;

  double number(const YAML::Node& n, const std::string& what) const { return rd_.number(n, what); }
  double positive(const YAML::Node& n, const std::string& what) const { return rd_.positive(n, what); }
  double number_in(const YAML::Node& n, const std::string& what, double lo, double hi, const std::string& unit = "") const {
    return rd_.number_in(n, what, lo, hi, unit);
  }
  long long integer(const YAML::Node& n, const std::string& what, long long lo, long long hi) const {
    return rd_.integer(n, what, lo, hi);
  }
  std::string text(const YAML::Node& n, const std::string& what) const { return rd_.text(n, what); }
  bool boolean(const YAML::Node& n, const std::string& what) const { return rd_.boolean(n, what); }
  std::string key(const YAML::Node& k, const std::string& what) const { return rd_.key(k, what); }
  YAML::Node list(const YAML::Node& map, const char* key, const std::string& what) const { return rd_.list(map, key, what); }

  // A non-empty list of numbers (at most 10000).
  std::vector<double> number_list(const YAML::Node& n, const std::string& what) const {
    if (!n.IsSequence() || n.size() == 0 || n.size() > 10000) fail(n, what + ": expected a list of 1 to 10000 numbers");
    std::vector<double> v;
    for (const auto& e : n) v.push_back(number(e, what));
    return v;
  }
  // A list of exactly N numbers.
  template <std::size_t N>
  std::array<double, N> numbers(const YAML::Node& n, const std::string& what) const {
    if (!n.IsSequence() || n.size() != N) fail(n, what + ": expected a list of " + std::to_string(N) + " numbers");
    std::array<double, N> v{};
    for (std::size_t k = 0; k < N; ++k) v[k] = number(n[k], what);
    return v;
  }
  // A name or a list of names; where[prefix + ":" + name] is set to each one's location.
  std::vector<std::string> names(const YAML::Node& n, const std::string& what, std::map<std::string, std::string>* where = nullptr,
                                 const std::string& prefix = "") const;
  // A map of name: number (joint angles, parameters), in file order ("expected a map of
  // joint: value" otherwise); where[prefix + ":" +
  // name] is set to each key's location.
  std::vector<std::pair<std::string, double>> named_numbers(const YAML::Node& n, const std::string& what,
                                                            std::map<std::string, std::string>* where = nullptr,
                                                            const std::string& prefix = "") const;

 private:
  Reader& rd_;
};

}  // namespace dmbd::yaml
