#include "dmbd/base/yaml_fields.hpp"

namespace dmbd::yaml {

YAML::Node Fields::required(const YAML::Node& n, const char* key, const std::string& what) const {
  if (!n[key]) fail(n, what + ": expected '" + key + "'");
  return n[key];
}

void Fields::keys(const YAML::Node& n, const std::string& what, std::initializer_list<const char*> allowed) const {
  if (!rd_.keys(n, std::vector<std::string>(allowed.begin(), allowed.end()), what)) throw Skip{};
}

std::vector<std::string> Fields::names(const YAML::Node& n, const std::string& what, std::map<std::string, std::string>* where,
                                       const std::string& prefix) const {
  std::vector<std::string> r;
  if (n.IsScalar()) {
    if (where) (*where)[prefix + ":" + n.Scalar()] = at(n);
    return {n.Scalar()};
  }
  if (!n.IsSequence()) fail(n, what + ": expected a list of names");
  for (const auto& e : n) {
    r.push_back(text(e, what));
    if (where) (*where)[prefix + ":" + r.back()] = at(e);
  }
  return r;
}

std::vector<std::pair<std::string, double>> Fields::named_numbers(const YAML::Node& n, const std::string& what,
                                                                  std::map<std::string, std::string>* where,
                                                                  const std::string& prefix) const {
  if (!n.IsMap()) fail(n, what + ": expected a map of joint: value");
  std::vector<std::pair<std::string, double>> r;
  for (const auto& kv : n) {
    const std::string k = key(kv.first, what);
    r.emplace_back(k, number(kv.second, what + "." + k));
    if (where) (*where)[prefix + ":" + r.back().first] = at(kv.first);
  }
  return r;
}

}  // namespace dmbd::yaml
