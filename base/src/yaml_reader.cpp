#include "dmbd/base/yaml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "dmbd/base/number_text.hpp"

namespace dmbd::yaml {

namespace {

std::string prefix(const std::string& context) { return context.empty() ? std::string() : context + ": "; }

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

std::string quoted(const std::string& text) {
  return "'" + (text.size() > 60 ? text.substr(0, 57) + "..." : text) + "'";
}

Reader::Reader(std::string file, NumberParser numbers) : file_(std::move(file)), numbers_(std::move(numbers)) {}

Location Reader::at(const YAML::Node& n, int offset) const {
  if (!n.IsDefined()) return Location{file_, 0, 0};
  const YAML::Mark m = n.Mark();
  if (m.is_null()) return Location{file_, 0, 0};
  const int quote = (n.IsScalar() && n.Tag() == "!") ? 1 : 0;  // inside a double-quoted scalar
  return Location{file_, m.line + 1, m.column + 1 + quote + offset};
}

void Reader::error(const Location& where, const std::string& message) {
  Diagnostic d{where, message};
  if (seen_.insert(d.str()).second) diagnostics_.push_back(std::move(d));  // once, however often it is read
}

void Reader::fail(const Location& where, const std::string& message) {
  error(where, message);
  throw Skip{};
}

std::string Reader::key(const YAML::Node& k, const std::string& context) {
  if (!k.IsScalar()) fail(k, prefix(context) + "a key must be a name, not a list, a map or empty");
  return k.Scalar();
}

bool Reader::keys(const YAML::Node& n, const std::vector<std::string>& allowed, const std::string& context,
                  const std::string& noun) {
  if (!n.IsDefined() || !n.IsMap()) fail(n, prefix(context) + "expected a map");
  const std::size_t before = diagnostics_.size();
  std::set<std::string> seen;
  for (const auto& kv : n) {
    guard([&] {
      const std::string k = key(kv.first, context);
      if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
        fail(kv.first, prefix(context) + "unknown " + noun + " " + quoted(k) + " (expected one of: " + join(allowed) + ")");
      if (!seen.insert(k).second) fail(kv.first, prefix(context) + noun + " " + quoted(k) + " is given twice");
    });
  }
  return diagnostics_.size() == before;
}

YAML::Node Reader::list(const YAML::Node& map, const std::string& key, const std::string& what) {
  const YAML::Node n = map[key];
  if (!n.IsDefined()) fail(map, what + ": expected a list");
  if (n.IsSequence()) return n;
  if (n.IsNull())  // an empty value has no place of its own: name its key's
    for (const auto& kv : map)
      if (kv.first.IsScalar() && kv.first.Scalar() == key) fail(kv.first, what + ": expected a list");
  fail(n, what + ": expected a list");
}

double Reader::number(const YAML::Node& n, const std::string& what) {
  if (!n.IsDefined() || !n.IsScalar()) fail(n, what + ": expected a number");
  double v = 0.0;
  try {
    v = numbers_(n.Scalar());
  } catch (const NumberError& e) {
    fail(at(n, std::max(0, e.column() - 1)), what + ": " + e.what());
  }
  if (!std::isfinite(v)) fail(n, what + ": expected a finite number, got " + quoted(n.Scalar()));
  return v;
}

double Reader::positive(const YAML::Node& n, const std::string& what) {
  const double v = number(n, what);
  if (!(v > 0)) fail(n, what + ": expected a positive number, got " + number_text(v));
  return v;
}

double Reader::number_in(const YAML::Node& n, const std::string& what, double lo, double hi, const std::string& unit) {
  const double v = number(n, what);
  const std::string u = unit.empty() ? std::string() : " " + unit;
  if (!(v >= lo && v <= hi))
    fail(n, what + ": expected a number from " + number_text(lo) + " to " + number_text(hi) + u + ", got " + number_text(v) + u);
  return v;
}

long long Reader::integer(const YAML::Node& n, const std::string& what, long long lo, long long hi) {
  const double v = number(n, what);
  if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
    fail(n, what + ": expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
  return static_cast<long long>(v);
}

std::string Reader::text(const YAML::Node& n, const std::string& what) {
  if (!n.IsDefined() || !n.IsScalar()) fail(n, what + ": expected a string");
  return n.Scalar();
}

bool Reader::boolean(const YAML::Node& n, const std::string& what) {
  if (!n.IsDefined() || !n.IsScalar()) fail(n, what + ": expected true or false");
  bool b = false;
  if (!YAML::convert<bool>::decode(n, b)) fail(n, what + ": expected true or false, got " + quoted(n.Scalar()));
  return b;
}

}  // namespace dmbd::yaml
