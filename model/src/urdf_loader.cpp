// URDF -> RobotDescription.
//
// Two readers of the same text:
//  1. TinyXML (the XML library urdfdom itself uses) keeps line numbers. It reports
//     malformed XML with its line, and a full pass over the document checks what
//     urdfdom either rejects with a message that names no line, or silently accepts
//     or drops (a NaN in an attribute drops a whole <inertial>, a loop or a second
//     parent can pass, an unknown geometry drops its <visual>): numbers, required
//     attributes, masses and inertias, joint types, limits and axes, the tree. It
//     also warns, once per element name, about tags that are ignored.
//  2. urdfdom (urdf::parseURDF) then builds the model that is converted: poses
//     (rpy -> quaternion), inertials, geometry, joints. Its console messages are
//     captured (nothing is printed); an error it still finds becomes a ModelError at
//     the line of the link or joint it names.
//
// Order: links[0] is the root, then the links in depth-first pre-order with the
// children of a link in the order their joints appear in the file; joints[i] is the
// parent joint of links[i + 1]. So a parent always comes before its child, and a
// leg's links and joints are contiguous.
//
// Mesh files are resolved and read by mesh_loader.cpp; each distinct file (and
// scale) is read once and shared. meshes_loaded counts the distinct URIs read,
// meshes_missing lists the distinct URIs that could not be found or read.
#include "dmbd/base/file.hpp"
#include "dmbd/base/number_text.hpp"
#include "dmbd/base/text.hpp"
#include "dmbd/model/error.hpp"
#include "convex_hull.hpp"
#include "dmbd/model/robot_description.hpp"
#include "mesh_loader.hpp"
#include "urdf_repairs.hpp"

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <system_error>
#include <tuple>

namespace dmbd::model {

namespace {

namespace fs = std::filesystem;

// Relative slack of the inertia triangle inequality: URDF exporters print 6 to 7
// significant digits, so a flat plate (I_zz = I_xx + I_yy exactly) can come out
// up to ~1e-6 of the trace on the wrong side.
constexpr double kTriangleSlack = 1e-6;

// File, line and element in every message: "FILE:LINE: link 'thigh': ...".
class Diag {
 public:
  explicit Diag(std::string label) : label_(std::move(label)) {}
  std::string at(int line) const { return line > 0 ? label_ + ":" + std::to_string(line) + ": " : label_ + ": "; }
  [[noreturn]] void fail(int line, const std::string& what) const { throw ModelError(at(line) + what); }

 private:
  std::string label_;
};

std::string hex(unsigned char c) {
  static const char* digits = "0123456789ABCDEF";
  return std::string("0x") + digits[c >> 4] + digits[c & 15];
}

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// ---------------------------------------------------------------- text guard --
//
// TinyXML 2.6.2 (the library urdfdom uses, and XmlPass) is not safe on every text:
//  - GetChar() steps over a whole UTF-8 sequence as announced by its lead byte, even
//    when the text ends (or holds a NUL) inside it, and then reads past the string's
//    terminator. The fuzzer saw this as heap-buffer-overflows in memcpy that did not
//    reproduce on replay: what lies past the terminator depends on the heap's history
//    (see fuzz/README.md). Valid UTF-8 without NUL bytes never triggers it.
//  - Elements are parsed (and freed) recursively: ~37,000 nested elements overflow an
//    8 MB stack. Nesting is bounded by the number of elements with content.
// So the text is checked first, with a located error.

constexpr int kMaxContainers = 10000;

// Length of the UTF-8 character at s[i], or 0 if it is not valid UTF-8 (RFC 3629).
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto at = [&](std::size_t k) { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u; };
  const unsigned c = at(i);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;  // the range of the second byte
  if (c >= 0xC2 && c <= 0xDF) {
    n = 1;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 2;
    lo = c == 0xE0 ? 0xA0 : lo;  // no overlong forms
    hi = c == 0xED ? 0x9F : hi;  // no surrogates
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 3;
    lo = c == 0xF0 ? 0x90 : lo;
    hi = c == 0xF4 ? 0x8F : hi;
  } else {
    return 0;
  }
  for (std::size_t k = 1; k <= n; ++k) {
    const unsigned x = at(i + k);
    if (x < (k == 1 ? lo : 0x80u) || x > (k == 1 ? hi : 0xBFu)) return 0;
  }
  return n + 1;
}

// "FILE:LINE: column C: what" for the byte s[i].
[[noreturn]] void fail_at(const std::string& s, std::size_t i, const Diag& d, const std::string& what) {
  const auto before = s.begin() + static_cast<std::ptrdiff_t>(i);
  const int line = 1 + static_cast<int>(std::count(s.begin(), before, '\n'));
  const std::size_t start = i == 0 ? std::string::npos : s.rfind('\n', i - 1);
  const std::size_t column = start == std::string::npos ? i + 1 : i - start;
  d.fail(line, "column " + std::to_string(column) + ": " + what);
}

// Does the tag that starts at s[i] == '<' end with "/>"? Quoted attribute values are
// skipped as TinyXML skips them (a quote right after '=' and blanks); where TinyXML
// would stop on an error this may answer either way, and then nothing nests deeper.
bool self_closing(const std::string& s, std::size_t i) {
  for (++i; i < s.size() && s[i] != '>'; ++i) {
    if (s[i] != '=') continue;
    while (i + 1 < s.size() && std::isspace(static_cast<unsigned char>(s[i + 1]))) ++i;
    if (i + 1 < s.size() && (s[i + 1] == '"' || s[i + 1] == '\'')) {
      const std::size_t close = s.find(s[i + 1], i + 2);
      if (close == std::string::npos) return false;
      i = close;
    }
  }
  return i < s.size() && s[i - 1] == '/';
}

void check_text(const std::string& s, const Diag& d) {
  int containers = 0;
  for (std::size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == 0) fail_at(s, i, d, "a NUL byte (expected XML text)");
    const std::size_t n = utf8_length(s, i);
    if (n == 0) fail_at(s, i, d, "byte " + hex(c) + " is not UTF-8 text (expected a UTF-8 file)");
    const unsigned char next = i + 1 < s.size() ? static_cast<unsigned char>(s[i + 1]) : 0;
    const bool element = c == '<' && (std::isalpha(next) || next == '_' || next >= 0x80);
    if (element && !self_closing(s, i) && ++containers > kMaxContainers)
      fail_at(s, i, d, "more than " + std::to_string(kMaxContainers) +
                           " elements with content (TinyXML parses nesting recursively; expected a smaller URDF)");
    i += n;
  }
}

// ---------------------------------------------------------------- XML pass ----

struct XVisual {
  int line = 0;                   // the <visual>/<collision>
  int mesh_line = 0;              // its <mesh>, when it is one
  std::optional<Eigen::Vector4d> rgba;
};

struct XLink {
  std::string name;
  int line = 0;
  std::vector<XVisual> visuals, collisions;
};

struct XJoint {
  std::string name, type, parent, child;
  int line = 0;
};

struct XRobot {
  std::string name;
  int line = 0;
  std::vector<XLink> links;
  std::vector<XJoint> joints;
  std::vector<std::string> warnings;
  // Links whose inertia breaks the triangle inequality (not strict): the <inertia> line.
  std::map<std::string, int> unbalanced;
  std::string world_joint;  // a joint from an undeclared 'world', not kept ("" if none)
};

class XmlPass {
 public:
  XmlPass(const Diag& diag, bool strict, XRobot& out) : d_(diag), strict_(strict), r_(out) {}

  void run(const TiXmlElement* robot) {
    r_.line = robot->Row();
    const char* name = robot->Attribute("name");
    if (!name || !*name) d_.fail(r_.line, "<robot> has no name attribute (expected <robot name=\"...\">)");
    r_.name = name;
    // Global materials first: a <visual> may name one defined after it.
    for (const TiXmlElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement())
      if (tag(e) == "material") material(e, "", true);
    for (const TiXmlElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string t = tag(e);
      if (t == "link") {
        link(e);
      } else if (t == "joint") {
        joint(e);
      } else if (t != "material") {
        unknown(e);
      }
    }
    if (r_.links.empty()) d_.fail(r_.line, "robot '" + r_.name + "': no <link> (expected at least one)");
    world_joint();
    tree();
    for (const std::string& n : unknown_order_) {
      const auto& u = unknown_.at(n);
      r_.warnings.push_back(d_.at(u.first) + "<" + n + "> ignored (not read by dmbd" +
                            (u.second > 1 ? "; " + std::to_string(u.second) + " elements" : std::string()) + ")");
    }
  }

 private:
  static std::string tag(const TiXmlElement* e) { return e->Value() ? e->Value() : ""; }

  void unknown(const TiXmlElement* e) {
    const std::string t = tag(e);
    auto it = unknown_.find(t);
    if (it == unknown_.end()) {
      unknown_[t] = {e->Row(), 1};
      unknown_order_.push_back(t);
    } else {
      ++it->second.second;
    }
  }

  // `n` whitespace-separated finite numbers from attribute `attr`, or `fallback`
  // when it is absent (an error if `required`).
  std::vector<double> numbers(const TiXmlElement* e, const char* attr, std::size_t n, const std::string& owner,
                              bool required, std::vector<double> fallback = {}) const {
    const char* text = e->Attribute(attr);
    const std::string where = "<" + tag(e) + " " + attr + "=\"" + (text ? text : "") + "\">";
    if (!text) {
      if (required)
        d_.fail(e->Row(), owner + "<" + tag(e) + "> has no " + attr + " attribute (expected " +
                              (n == 1 ? "a number" : std::to_string(n) + " numbers") + ")");
      if (fallback.empty()) fallback.assign(n, 0.0);
      return fallback;
    }
    std::vector<double> v;
    const char* p = text;
    const char* end = text + std::strlen(text);
    while (true) {
      while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
      if (p == end) break;
      const char* q = p;
      while (q < end && !std::isspace(static_cast<unsigned char>(*q))) ++q;
      const std::string token(p, q);
      const char* b = p;
      if (*b == '+') ++b;
      double x = 0;
      const auto res = std::from_chars(b, q, x);
      if (res.ec == std::errc::result_out_of_range)
        d_.fail(e->Row(), owner + where + ": '" + token + "' is out of the range of a double (expected a finite number)");
      if (res.ec != std::errc() || res.ptr != q)
        d_.fail(e->Row(), owner + where + ": '" + token + "' is not a number");
      if (!std::isfinite(x)) d_.fail(e->Row(), owner + where + ": '" + token + "' is not a finite number");
      v.push_back(x);
      p = q;
    }
    if (v.size() != n)
      d_.fail(e->Row(), owner + where + ": expected " + (n == 1 ? std::string("one number") : std::to_string(n) + " numbers") +
                            ", found " + std::to_string(v.size()));
    return v;
  }
  double number(const TiXmlElement* e, const char* attr, const std::string& owner, bool required, double fallback = 0) const {
    return numbers(e, attr, 1, owner, required, {fallback})[0];
  }
  double non_negative(const TiXmlElement* e, const char* attr, const std::string& owner, bool required,
                      const char* unit) const {
    const double v = number(e, attr, owner, required);
    if (v < 0)
      d_.fail(e->Row(), owner + "<" + tag(e) + " " + attr + "=\"" + e->Attribute(attr) + "\">: expected a value >= 0" +
                            (*unit ? std::string(" ") + unit : std::string()));
    return v;
  }

  // The children of `e` other than `known` are recorded as unknown; returns the
  // known ones by name. A known child may appear once, unless it is `repeatable`
  // (those are not returned).
  std::map<std::string, const TiXmlElement*> children(const TiXmlElement* e, std::initializer_list<const char*> known,
                                                      const std::string& owner,
                                                      std::initializer_list<const char*> repeatable = {}) {
    std::map<std::string, const TiXmlElement*> found;
    for (const TiXmlElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string t = tag(c);
      bool is_known = false, rep = false;
      for (const char* k : known) is_known = is_known || t == k;
      for (const char* k : repeatable) rep = rep || t == k;
      if (!is_known) {
        unknown(c);
        continue;
      }
      if (rep) continue;
      if (found.count(t))
        d_.fail(c->Row(), owner + "a second <" + t + "> in <" + tag(e) + "> (line " + std::to_string(found[t]->Row()) +
                              " has the first; expected one)");
      found[t] = c;
    }
    return found;
  }

  void origin(const TiXmlElement* o, const std::string& owner) {
    if (!o) return;
    children(o, {}, owner);
    numbers(o, "xyz", 3, owner, false);
    numbers(o, "rpy", 3, owner, false);
  }

  // Material of a <visual> (inline) or at robot level (global): its colour, if any.
  std::optional<Eigen::Vector4d> material(const TiXmlElement* m, const std::string& owner, bool global) {
    const char* name = m->Attribute("name");
    if (global && (!name || !*name)) d_.fail(m->Row(), "<material> at robot level has no name attribute");
    const std::string own = global ? "material '" + std::string(name) + "': " : owner;
    const auto kids = children(m, {"color", "texture"}, own);
    std::optional<Eigen::Vector4d> rgba;
    if (kids.count("color")) {
      const auto v = numbers(kids.at("color"), "rgba", 4, own, true);
      for (double x : v)
        if (x < 0 || x > 1)
          d_.fail(kids.at("color")->Row(), own + "<color rgba=\"" + kids.at("color")->Attribute("rgba") +
                                               "\">: expected 4 numbers in [0, 1]");
      rgba = Eigen::Vector4d(v[0], v[1], v[2], v[3]);
    }
    if (kids.count("texture") && !kids.at("texture")->Attribute("filename"))
      d_.fail(kids.at("texture")->Row(), own + "<texture> has no filename attribute");
    if (global) {
      if (rgba) global_colors_[name] = *rgba;
      return rgba;
    }
    if (!rgba && name && *name) {
      const auto it = global_colors_.find(name);
      if (it != global_colors_.end()) rgba = it->second;
    }
    return rgba;
  }

  XVisual shape(const TiXmlElement* e, const std::string& owner, bool visual) {
    XVisual out;
    out.line = e->Row();
    // A <collision> may carry a <material> too (some exporters write one); it is ignored.
    const auto kids = children(e, {"origin", "geometry", "material"}, owner);
    origin(kids.count("origin") ? kids.at("origin") : nullptr, owner);
    if (!kids.count("geometry"))
      d_.fail(e->Row(), owner + "<" + tag(e) + "> has no <geometry> (expected one of <box>, <cylinder>, <sphere>, <mesh>)");
    const TiXmlElement* g = kids.at("geometry");
    const TiXmlElement* s = g->FirstChildElement();
    if (!s) d_.fail(g->Row(), owner + "<geometry> is empty (expected one of <box>, <cylinder>, <sphere>, <mesh>)");
    if (const TiXmlElement* extra = s->NextSiblingElement())
      r_.warnings.push_back(d_.at(extra->Row()) + owner + "<geometry> holds more than one shape; only the first, <" +
                            tag(s) + ">, is used");
    const std::string t = tag(s);
    children(s, {}, owner);
    if (t == "box") {
      const auto v = numbers(s, "size", 3, owner, true);
      if (v[0] < 0 || v[1] < 0 || v[2] < 0)
        d_.fail(s->Row(), owner + "<box size=\"" + s->Attribute("size") + "\">: expected sizes >= 0 m");
    } else if (t == "cylinder") {
      non_negative(s, "radius", owner, true, "m");
      non_negative(s, "length", owner, true, "m");
    } else if (t == "sphere") {
      non_negative(s, "radius", owner, true, "m");
    } else if (t == "mesh") {
      const char* f = s->Attribute("filename");
      if (!f || !*f) d_.fail(s->Row(), owner + "<mesh> has no filename attribute");
      numbers(s, "scale", 3, owner, false, {1.0, 1.0, 1.0});
      out.mesh_line = s->Row();
    } else {
      d_.fail(s->Row(), owner + "<" + t + "> is not a URDF geometry (expected <box>, <cylinder>, <sphere> or <mesh>)");
    }
    if (visual && kids.count("material")) out.rgba = material(kids.at("material"), owner, false);
    return out;
  }

  void link(const TiXmlElement* e) {
    XLink l;
    l.line = e->Row();
    const char* name = e->Attribute("name");
    if (!name || !*name) d_.fail(l.line, "<link> has no name attribute");
    l.name = name;
    const std::string owner = "link '" + l.name + "': ";
    if (const auto it = link_line_.find(l.name); it != link_line_.end())
      d_.fail(l.line, owner + "a second link of that name (the first is at line " + std::to_string(it->second) + ")");
    link_line_[l.name] = l.line;
    const auto kids = children(e, {"inertial", "visual", "collision"}, owner, {"visual", "collision"});
    if (kids.count("inertial")) inertial(kids.at("inertial"), l.name, owner);
    for (const TiXmlElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (tag(c) == "visual") l.visuals.push_back(shape(c, owner, true));
      if (tag(c) == "collision") l.collisions.push_back(shape(c, owner, false));
    }
    r_.links.push_back(std::move(l));
  }

  void inertial(const TiXmlElement* e, const std::string& link, const std::string& owner) {
    const auto kids = children(e, {"origin", "mass", "inertia"}, owner);
    origin(kids.count("origin") ? kids.at("origin") : nullptr, owner);
    if (!kids.count("mass")) d_.fail(e->Row(), owner + "<inertial> has no <mass value=\"...\"/> (kg)");
    if (!kids.count("inertia"))
      d_.fail(e->Row(), owner + "<inertial> has no <inertia ixx=\"..\" ixy=\"..\" ixz=\"..\" iyy=\"..\" iyz=\"..\" izz=\"..\"/> (kg m^2)");
    const TiXmlElement* m = kids.at("mass");
    const TiXmlElement* in = kids.at("inertia");
    children(m, {}, owner);
    children(in, {}, owner);
    const double mass = number(m, "value", owner, true);
    if (mass < 0) d_.fail(m->Row(), owner + "mass " + number_text(mass) + " kg is negative (expected >= 0)");
    const char* names[6] = {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"};
    double v[6];
    for (int k = 0; k < 6; ++k) v[k] = number(in, names[k], owner, true);
    Eigen::Matrix3d I;
    I << v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5];
    const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
    const std::string moments = number_text(ev[0]) + ", " + number_text(ev[1]) + ", " + number_text(ev[2]) + " kg m^2";
    const int line = in->Row();
    if (mass == 0) {
      if (I.isZero(0)) return;
      // A massless link with an inertia: kept as written (the plant decides), but
      // it is probably a mistake (a dummy link exported with a placeholder).
      if (ev[0] < 0)
        d_.fail(line, owner + "inertia is not positive semi-definite (principal moments " + moments +
                          "; expected all >= 0)");
      r_.warnings.push_back(d_.at(line) + owner + "mass 0 with a nonzero inertia (principal moments " + moments +
                            "); the inertia is kept");
      return;
    }
    if (!(ev[0] > 0))
      d_.fail(line, owner + "inertia is not positive definite (principal moments " + moments +
                        "; expected all > 0 for a link with mass " + number_text(mass) + " kg)");
    if (ev[0] + ev[1] >= ev[2] - kTriangleSlack * ev.sum()) return;
    if (strict_)
      d_.fail(line, owner + "inertia violates the triangle inequality (principal moments " + number_text(ev[0]) + " + " +
                        number_text(ev[1]) + " < " + number_text(ev[2]) + " kg m^2; expected each <= the sum of the other two; " +
                        "strict: not repaired by balanceinertia)");
    r_.unbalanced[link] = line;
  }

  void joint(const TiXmlElement* e) {
    XJoint j;
    j.line = e->Row();
    const char* name = e->Attribute("name");
    if (!name || !*name) d_.fail(j.line, "<joint> has no name attribute");
    j.name = name;
    const std::string owner = "joint '" + j.name + "': ";
    if (const auto it = joint_line_.find(j.name); it != joint_line_.end())
      d_.fail(j.line, owner + "a second joint of that name (the first is at line " + std::to_string(it->second) + ")");
    joint_line_[j.name] = j.line;
    const char* type = e->Attribute("type");
    if (!type) d_.fail(j.line, owner + "no type attribute (expected fixed, revolute, continuous, prismatic, floating or planar)");
    j.type = type;
    static const std::set<std::string> kTypes = {"fixed", "revolute", "continuous", "prismatic", "floating", "planar"};
    if (!kTypes.count(j.type))
      d_.fail(j.line, owner + "unknown type '" + j.type + "' (expected fixed, revolute, continuous, prismatic, floating or planar)");
    const auto kids = children(
        e, {"origin", "parent", "child", "axis", "limit", "dynamics", "calibration", "mimic", "safety_controller"}, owner);
    origin(kids.count("origin") ? kids.at("origin") : nullptr, owner);
    for (const char* pc : {"parent", "child"}) {
      const char* l = kids.count(pc) ? kids.at(pc)->Attribute("link") : nullptr;
      if (!l || !*l) d_.fail(kids.count(pc) ? kids.at(pc)->Row() : j.line, owner + "no <" + pc + " link=\"...\"/>");
      (std::strcmp(pc, "parent") == 0 ? j.parent : j.child) = l;
      children(kids.at(pc), {}, owner);
    }
    const bool moves = j.type != "fixed" && j.type != "floating";
    if (kids.count("axis")) {
      const TiXmlElement* a = kids.at("axis");
      children(a, {}, owner);
      const auto v = numbers(a, "xyz", 3, owner, moves, {1.0, 0.0, 0.0});
      if (moves && Eigen::Vector3d(v[0], v[1], v[2]).norm() == 0)
        d_.fail(a->Row(), owner + "<axis xyz=\"" + a->Attribute("xyz") + "\">: the axis is zero (expected a direction)");
    }
    const bool needs_limit = j.type == "revolute" || j.type == "prismatic";
    if (kids.count("limit")) {
      const TiXmlElement* l = kids.at("limit");
      children(l, {}, owner);
      const double lo = number(l, "lower", owner, false), hi = number(l, "upper", owner, false);
      const bool angular = j.type != "prismatic";
      non_negative(l, "effort", owner, true, angular ? "N m" : "N");
      non_negative(l, "velocity", owner, true, angular ? "rad/s" : "m/s");
      if (needs_limit && lo > hi)
        d_.fail(l->Row(), owner + "<limit lower=\"" + number_text(lo) + "\" upper=\"" + number_text(hi) + "\">: lower is above upper");
    } else if (needs_limit) {
      d_.fail(j.line, owner + "a " + j.type +
                          " joint needs <limit lower=\"..\" upper=\"..\" effort=\"..\" velocity=\"..\"/>" +
                          (j.type == "revolute" ? " (use type=\"continuous\" for a joint without position limits)"
                                                : std::string()));
    }
    if (kids.count("dynamics")) {
      const TiXmlElement* dy = kids.at("dynamics");
      children(dy, {}, owner);
      if (!dy->Attribute("damping") && !dy->Attribute("friction"))
        d_.fail(dy->Row(), owner + "<dynamics> has neither damping nor friction");
      non_negative(dy, "damping", owner, false, "");
      non_negative(dy, "friction", owner, false, "");
    }
    if (kids.count("calibration")) {
      children(kids.at("calibration"), {}, owner);
      number(kids.at("calibration"), "rising", owner, false);
      number(kids.at("calibration"), "falling", owner, false);
    }
    if (kids.count("safety_controller")) {
      const TiXmlElement* s = kids.at("safety_controller");
      children(s, {}, owner);
      for (const char* a : {"soft_lower_limit", "soft_upper_limit", "k_position"}) number(s, a, owner, false);
      number(s, "k_velocity", owner, true);
    }
    if (kids.count("mimic")) {
      const TiXmlElement* mi = kids.at("mimic");
      children(mi, {}, owner);
      if (!mi->Attribute("joint") || !*mi->Attribute("joint"))
        d_.fail(mi->Row(), owner + "<mimic> has no joint attribute");
      number(mi, "multiplier", owner, false, 1.0);
      number(mi, "offset", owner, false);
      r_.warnings.push_back(d_.at(mi->Row()) + owner + "<mimic joint=\"" + mi->Attribute("joint") +
                            "\"> ignored (the joint moves on its own)");
    }
    r_.joints.push_back(std::move(j));
  }

  // A joint from the undeclared link 'world' (the ROS and Gazebo name of the ground, as
  // in Simbody's Atlas example) is not kept: its child becomes the root, and the plant's
  // base mode (floating or fixed) says how the root is held. Fixed and floating only.
  void world_joint() {
    if (link_line_.count("world")) return;
    for (auto it = r_.joints.begin(); it != r_.joints.end(); ++it) {
      if (it->parent != "world") continue;
      const std::string owner = "joint '" + it->name + "': ";
      if (it->type != "fixed" && it->type != "floating")
        d_.fail(it->line, owner + "a " + it->type + " joint from the undeclared link 'world' (expected fixed or " +
                              "floating, or a <link name=\"world\"/>)");
      r_.warnings.push_back(d_.at(it->line) + owner + "attaches link '" + it->child + "' to the undeclared link " +
                            "'world' (" + it->type + "): the joint and its origin are not kept; '" + it->child +
                            "' is the root, held as the plant's base mode says (floating or fixed)");
      r_.world_joint = it->name;
      r_.joints.erase(it);
      return;
    }
  }

  // One root, one parent per link, every link reached from the root.
  void tree() {
    std::map<std::string, const XJoint*> parent_joint;
    for (const XJoint& j : r_.joints) {
      const std::string owner = "joint '" + j.name + "': ";
      if (!link_line_.count(j.parent))
        d_.fail(j.line, owner + "parent link '" + j.parent + "' is not defined (no <link name=\"" + j.parent + "\">)");
      if (!link_line_.count(j.child))
        d_.fail(j.line, owner + "child link '" + j.child + "' is not defined (no <link name=\"" + j.child + "\">)");
      if (j.parent == j.child) d_.fail(j.line, owner + "parent and child are the same link '" + j.child + "'");
      if (const auto it = parent_joint.find(j.child); it != parent_joint.end())
        d_.fail(j.line, owner + "link '" + j.child + "' already has the parent joint '" + it->second->name + "' (line " +
                            std::to_string(it->second->line) +
                            "); a URDF is a tree, one parent per link (close a loop with a constraint instead)");
      parent_joint[j.child] = &j;
    }
    const XLink* root = nullptr;
    for (const XLink& l : r_.links) {
      if (parent_joint.count(l.name)) continue;
      if (root)
        d_.fail(l.line, "link '" + l.name + "': a second root (link '" + root->name + "' at line " +
                            std::to_string(root->line) + " has no parent joint either); expected one root, every other "
                            "link the child of a joint");
      root = &l;
    }
    // Links not reached from the root (or no root at all) sit on a loop: each has
    // one parent, so following parents from one of them comes back to a link seen.
    std::set<std::string> reached;
    if (root) {
      std::map<std::string, std::vector<const XJoint*>> kids;
      for (const XJoint& j : r_.joints) kids[j.parent].push_back(&j);
      std::vector<std::string> stack{root->name};
      while (!stack.empty()) {
        const std::string l = stack.back();
        stack.pop_back();
        reached.insert(l);
        for (const XJoint* j : kids[l]) stack.push_back(j->child);
      }
    }
    for (const XLink& l : r_.links) {
      if (reached.count(l.name)) continue;
      std::vector<std::string> path{l.name};
      std::string cur = l.name;
      while (true) {
        cur = parent_joint.at(cur)->parent;
        const auto it = std::find(path.begin(), path.end(), cur);
        if (it != path.end()) {
          // The loop is path[it..] (child to parent); print it parent to child.
          std::vector<std::string> loop(it, path.end());
          std::reverse(loop.begin(), loop.end());
          const XJoint* last = nullptr;
          for (const std::string& c : loop)
            if (!last || parent_joint.at(c)->line > last->line) last = parent_joint.at(c);
          std::string text;
          for (const std::string& c : loop) text += c + " -> ";
          text += loop.front();
          d_.fail(last->line, "joint '" + last->name + "': loop in the kinematic tree: " + text +
                                  (root ? std::string(" (not connected to the root '") + root->name + "')"
                                        : std::string(" (so no link is the root)")) +
                                  "; a URDF must be a tree");
        }
        path.push_back(cur);
      }
    }
  }

  const Diag& d_;
  bool strict_;
  XRobot& r_;
  std::map<std::string, int> link_line_, joint_line_;
  std::map<std::string, Eigen::Vector4d> global_colors_;
  std::map<std::string, std::pair<int, int>> unknown_;  // tag -> first line, count
  std::vector<std::string> unknown_order_;
};

// ------------------------------------------------------------- urdfdom --------

class Capture : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) messages.emplace_back(level, one_line(text));
  }
  std::vector<std::pair<console_bridge::LogLevel, std::string>> messages;
};

// The line of the link or joint a urdfdom message names ("[name]" or "'name'").
int line_of_message(const std::string& msg, const XRobot& x) {
  for (std::size_t i = 0; i < msg.size(); ++i) {
    const char open = msg[i];
    if (open != '[' && open != '\'') continue;
    const char close = open == '[' ? ']' : '\'';
    const auto j = msg.find(close, i + 1);
    if (j == std::string::npos) break;
    const std::string name = msg.substr(i + 1, j - i - 1);
    for (const XJoint& jt : x.joints)
      if (jt.name == name) return jt.line;
    for (const XLink& l : x.links)
      if (l.name == name) return l.line;
    i = j;
  }
  return x.line;
}

urdf::ModelInterfaceSharedPtr run_urdfdom(const std::string& xml, const Diag& d, const XRobot& x,
                                          std::vector<std::string>& warnings) {
  static std::mutex mutex;  // console_bridge's handler and level are process-wide
  Capture capture;
  urdf::ModelInterfaceSharedPtr model;
  std::string thrown;
  {
    std::lock_guard<std::mutex> lock(mutex);
    const auto level = console_bridge::getLogLevel();
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
    console_bridge::useOutputHandler(&capture);
    try {
      model = urdf::parseURDF(xml);
    } catch (const std::exception& e) {
      thrown = one_line(e.what());
    }
    console_bridge::restorePreviousOutputHandler();
    console_bridge::setLogLevel(level);
  }
  for (const auto& m : capture.messages)
    if (m.first >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) d.fail(line_of_message(m.second, x), "urdfdom: " + m.second);
  if (!thrown.empty()) d.fail(x.line, "urdfdom: " + thrown);
  if (!model) d.fail(x.line, "urdfdom could not read the robot");
  std::set<std::string> seen;
  for (const auto& m : capture.messages)
    if (seen.insert(m.second).second) warnings.push_back(d.at(line_of_message(m.second, x)) + "urdfdom: " + m.second);
  return model;
}

Eigen::Isometry3d to_eigen(const urdf::Pose& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return X;
}

Eigen::Vector3d to_eigen(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

Geometry convert_geometry(const urdf::GeometrySharedPtr& g) {
  Geometry out;
  switch (g->type) {
    case urdf::Geometry::BOX:
      out.kind = Geometry::Kind::Box;
      out.box_size_m = to_eigen(std::static_pointer_cast<urdf::Box>(g)->dim);
      break;
    case urdf::Geometry::CYLINDER: {
      const auto c = std::static_pointer_cast<urdf::Cylinder>(g);
      out.kind = Geometry::Kind::Cylinder;
      out.radius_m = c->radius;
      out.length_m = c->length;
      break;
    }
    case urdf::Geometry::SPHERE:
      out.kind = Geometry::Kind::Sphere;
      out.radius_m = std::static_pointer_cast<urdf::Sphere>(g)->radius;
      break;
    case urdf::Geometry::MESH: {
      const auto m = std::static_pointer_cast<urdf::Mesh>(g);
      out.kind = Geometry::Kind::Mesh;
      out.mesh_uri = m->filename;
      out.mesh_scale = to_eigen(m->scale);
      break;
    }
  }
  return out;
}

JointType convert_type(int t, const Diag& d, const XJoint& x) {
  switch (t) {
    case urdf::Joint::FIXED: return JointType::Fixed;
    case urdf::Joint::REVOLUTE: return JointType::Revolute;
    case urdf::Joint::CONTINUOUS: return JointType::Continuous;
    case urdf::Joint::PRISMATIC: return JointType::Prismatic;
    case urdf::Joint::FLOATING: return JointType::Floating;
    case urdf::Joint::PLANAR: return JointType::Planar;
    default: d.fail(x.line, "joint '" + x.name + "': unknown type '" + x.type + "'");
  }
}

// Reads each mesh once per (file, scale); fills meshes_loaded/missing and warnings; gives
// each collision mesh its contact points (Geometry::hull_m).
class MeshReader {
 public:
  MeshReader(const Diag& d, const std::string& base_dir, const UrdfOptions& o, RobotDescription& r)
      : d_(d), base_dir_(base_dir), o_(o), r_(r) {}

  void load(Geometry& g, int line, const std::string& owner, bool collision) {
    if (g.kind != Geometry::Kind::Mesh || !o_.load_meshes) return;
    std::vector<std::string> tried;
    const auto path = detail::resolve_mesh_uri(g.mesh_uri, base_dir_, o_.package_paths, &tried);
    std::string problem;
    if (!path) {
      problem = "mesh '" + g.mesh_uri + "' not found (tried " + list(tried) + ")";
    } else {
      const auto key = std::make_tuple(*path, g.mesh_scale.x(), g.mesh_scale.y(), g.mesh_scale.z());
      auto it = cache_.find(key);
      if (it == cache_.end()) {
        std::string error;
        std::shared_ptr<const TriangleMesh> m = detail::load_mesh_file(*path, g.mesh_scale, &error);
        it = cache_.emplace(key, std::make_pair(m, error)).first;
      }
      g.mesh = it->second.first;
      if (!g.mesh) problem = "mesh '" + g.mesh_uri + "' (" + *path + ") cannot be read: " + it->second.second;
    }
    if (problem.empty()) {
      if (loaded_.insert(g.mesh_uri).second) ++r_.meshes_loaded;
      if (collision) contact_points(g, line, owner);
      return;
    }
    if (o_.strict) d_.fail(line, owner + problem + " (strict: every mesh must load)");
    // One warning per missing URI, at its first use; a collision that uses it is named
    // there as skipped (a mesh without a file cannot touch the ground).
    const auto w = warned_.find(g.mesh_uri);
    if (w == warned_.end()) {
      r_.meshes_missing.push_back(g.mesh_uri);
      warned_[g.mesh_uri] = r_.warnings.size();
      r_.warnings.push_back(d_.at(line) + owner + problem + (collision ? "; this collision shape is skipped (no contact)" : ""));
    } else if (collision) {
      r_.warnings[w->second] += "; the collision of " + owner.substr(0, owner.size() - 2) + " at line " +
                                std::to_string(line) + " is skipped (no contact)";
    }
  }

 private:
  static std::string list(const std::vector<std::string>& tried) {
    if (tried.empty()) return "nothing";
    std::string s;
    const std::size_t shown = std::min<std::size_t>(tried.size(), 4);
    for (std::size_t i = 0; i < shown; ++i) s += (i ? ", " : "") + tried[i];
    if (tried.size() > shown) s += " and " + std::to_string(tried.size() - shown) + " more";
    return s;
  }

  // The convex hull's vertices, at most kMaxHullPoints (one warning per shape above it).
  void contact_points(Geometry& g, int line, const std::string& owner) {
    auto it = hulls_.find(g.mesh.get());
    if (it == hulls_.end()) {
      std::size_t size = 0;
      std::vector<Eigen::Vector3d> points = detail::mesh_contact_points(*g.mesh, detail::kMaxHullPoints, &size);
      it = hulls_.emplace(g.mesh.get(), std::make_pair(std::move(points), size)).first;
    }
    g.hull_m = it->second.first;
    if (it->second.second > detail::kMaxHullPoints)
      r_.warnings.push_back(d_.at(line) + owner + "collision mesh '" + g.mesh_uri + "' has " + std::to_string(it->second.second) +
                            " convex-hull vertices; contact uses " + std::to_string(detail::kMaxHullPoints) +
                            " of them (farthest-point sampling)");
  }

  const Diag& d_;
  std::string base_dir_;
  const UrdfOptions& o_;
  RobotDescription& r_;
  std::map<std::string, std::size_t> warned_;  // missing URI -> its warning
  std::map<const TriangleMesh*, std::pair<std::vector<Eigen::Vector3d>, std::size_t>> hulls_;
  std::map<std::tuple<std::string, double, double, double>,
           std::pair<std::shared_ptr<const TriangleMesh>, std::string>> cache_;
  std::set<std::string> loaded_;
};

}  // namespace

RobotDescription parse_urdf(const std::string& xml, const std::string& base_dir, const std::string& label,
                            const UrdfOptions& options) {
  const Diag d(label.empty() ? std::string("<urdf>") : label);
  check_text(xml, d);
  TiXmlDocument doc;
  doc.Parse(xml.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (doc.Error()) {
    const int row = doc.ErrorRow() > 0 ? doc.ErrorRow() : 1;
    d.fail(row, "malformed XML: " + one_line(doc.ErrorDesc()) + " (column " + std::to_string(doc.ErrorCol()) + ")");
  }
  const TiXmlElement* root = doc.RootElement();
  if (!root) d.fail(1, "no <robot> element (the document has no element)");
  if (std::string(root->Value()) != "robot")
    d.fail(root->Row(), std::string("the top element is <") + root->Value() + ">, expected <robot name=\"...\">");
  XRobot x;
  XmlPass(d, options.strict, x).run(root);

  RobotDescription r;
  r.warnings = x.warnings;
  // urdfdom refuses a parent link that is not declared: it is given a 'world' on the
  // line of </robot> (no other line moves), and its joint is not converted.
  std::string for_urdfdom = xml;
  if (const auto end = for_urdfdom.rfind("</robot>"); !x.world_joint.empty() && end != std::string::npos)
    for_urdfdom.insert(end, "<link name=\"world\"/>");
  const urdf::ModelInterfaceSharedPtr model = run_urdfdom(for_urdfdom, d, x, r.warnings);
  r.name = model->getName();

  // Depth-first pre-order from the root, children in file order.
  std::map<std::string, std::vector<const XJoint*>> kids;
  std::set<std::string> children;
  for (const XJoint& j : x.joints) {
    kids[j.parent].push_back(&j);
    children.insert(j.child);
  }
  const XLink* xroot = nullptr;
  for (const XLink& l : x.links)
    if (!children.count(l.name)) xroot = &l;
  std::map<std::string, const XLink*> xlink;
  for (const XLink& l : x.links) xlink[l.name] = &l;

  MeshReader meshes(d, base_dir, options, r);
  auto add_link = [&](const XLink& xl) {
    const auto it = model->links_.find(xl.name);
    if (it == model->links_.end() || !it->second) d.fail(xl.line, "link '" + xl.name + "': urdfdom did not keep it");
    const urdf::Link& ul = *it->second;
    const std::string owner = "link '" + xl.name + "': ";
    Link l;
    l.name = xl.name;
    if (ul.inertial) {
      l.mass_kg = ul.inertial->mass;
      const Eigen::Isometry3d X = to_eigen(ul.inertial->origin);
      Eigen::Matrix3d I;
      const urdf::Inertial& in = *ul.inertial;
      I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      l.com_m = X.translation();
      l.inertia_kgm2 = X.linear() * I * X.linear().transpose();
      if (const auto u = x.unbalanced.find(xl.name); u != x.unbalanced.end())
        detail::balance_link_inertia(l, d.at(u->second), r);
    }
    auto shapes = [&](const auto& array, const std::vector<XVisual>& xs, std::vector<Shape>& out, bool visual) {
      if (array.size() != xs.size())
        d.fail(xl.line, owner + "urdfdom kept " + std::to_string(array.size()) + " of " + std::to_string(xs.size()) +
                            (visual ? " visuals" : " collisions"));
      for (std::size_t k = 0; k < array.size(); ++k) {
        const auto& v = *array[k];
        Shape s;
        s.name = v.name;
        s.X_LG = to_eigen(v.origin);
        s.geometry = convert_geometry(v.geometry);
        if (visual && xs[k].rgba) s.rgba = *xs[k].rgba;
        meshes.load(s.geometry, xs[k].mesh_line ? xs[k].mesh_line : xs[k].line, owner, !visual);
        out.push_back(std::move(s));
      }
    };
    shapes(ul.visual_array, xl.visuals, l.visuals, true);
    shapes(ul.collision_array, xl.collisions, l.collisions, false);
    r.links.push_back(std::move(l));
  };
  add_link(*xroot);
  std::vector<const XJoint*> stack;
  for (auto it = kids[xroot->name].rbegin(); it != kids[xroot->name].rend(); ++it) stack.push_back(*it);
  while (!stack.empty()) {
    const XJoint& xj = *stack.back();
    stack.pop_back();
    const auto it = model->joints_.find(xj.name);
    if (it == model->joints_.end() || !it->second) d.fail(xj.line, "joint '" + xj.name + "': urdfdom did not keep it");
    const urdf::Joint& uj = *it->second;
    Joint j;
    j.name = xj.name;
    j.type = convert_type(uj.type, d, xj);
    j.parent = uj.parent_link_name;
    j.child = uj.child_link_name;
    j.X_PJ = to_eigen(uj.parent_to_joint_origin_transform);
    j.axis = to_eigen(uj.axis);
    if (j.type == JointType::Fixed || j.type == JointType::Floating) {
      // urdfdom does not read <axis> for these; keep the default unless one is given.
      if (j.axis.norm() == 0) j.axis = Eigen::Vector3d::UnitX();
    }
    j.axis.normalize();
    if (uj.limits) {
      j.has_limits = j.type == JointType::Revolute || j.type == JointType::Prismatic;
      if (j.has_limits) {
        j.lower = uj.limits->lower;
        j.upper = uj.limits->upper;
      }
      j.effort = uj.limits->effort;
      j.velocity = uj.limits->velocity;
    }
    if (uj.dynamics) {
      j.damping = uj.dynamics->damping;
      j.friction = uj.dynamics->friction;
    }
    r.joints.push_back(std::move(j));
    add_link(*xlink.at(xj.child));
    const auto& ck = kids[xj.child];
    for (auto c = ck.rbegin(); c != ck.rend(); ++c) stack.push_back(*c);
  }
  std::map<std::string, int> joint_line;
  for (const XJoint& j : x.joints) joint_line[j.name] = j.line;
  detail::check_massless_moving(r, [&](const std::string& joint) { return d.at(joint_line[joint]); }, options.strict);
  return r;
}

RobotDescription load_urdf(const std::string& path, const UrdfOptions& options) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw ModelError(path + ": is a folder (expected a URDF file)");
  std::string text;
  if (const auto reason = try_read_text_file(path, text)) throw ModelError(path + ": cannot open the file (" + *reason + ")");
  if (const auto d = not_text(text, path)) throw ModelError(d->where.str() + ": " + d->message);
  const std::string base = fs::path(path).parent_path().string();
  RobotDescription r = parse_urdf(text, base.empty() ? "." : base, path, options);
  r.source = path;
  return r;
}

ModelSummary summarize(const RobotDescription& robot) {
  ModelSummary s;
  s.name = robot.name;
  s.links = robot.links.size();
  for (const Joint& j : robot.joints) {
    switch (j.type) {
      case JointType::Fixed: ++s.fixed; break;
      case JointType::Revolute: ++s.revolute; break;
      case JointType::Continuous: ++s.continuous; break;
      case JointType::Prismatic: ++s.prismatic; break;
      case JointType::Floating: ++s.floating; break;
      case JointType::Planar: ++s.planar; break;
    }
  }
  s.dof = s.revolute + s.continuous + s.prismatic;
  s.total_mass_kg = robot.total_mass_kg();
  s.meshes_loaded = robot.meshes_loaded;
  s.meshes_missing = robot.meshes_missing;
  // Height: z extent of every visual in the default pose (exact for primitives).
  const auto X_WL = default_pose_link_frames(robot);
  double lo = INFINITY, hi = -INFINITY;
  auto span = [&](double a, double b) {
    lo = std::min(lo, a);
    hi = std::max(hi, b);
  };
  for (std::size_t l = 0; l < robot.links.size(); ++l) {
    for (const Shape& sh : robot.links[l].visuals) {
      const Eigen::Isometry3d X = X_WL[l] * sh.X_LG;
      const Geometry& g = sh.geometry;
      const double cz = X.translation().z();
      switch (g.kind) {
        case Geometry::Kind::Box: {
          // Half extent along world z: sum of |R_zk| * half size k.
          const double h = 0.5 * X.linear().row(2).cwiseAbs().dot(g.box_size_m.cwiseAbs());
          span(cz - h, cz + h);
          break;
        }
        case Geometry::Kind::Sphere:
          span(cz - g.radius_m, cz + g.radius_m);
          break;
        case Geometry::Kind::Cylinder: {
          // Axis a = R e_z: rims at c +- (L/2) a; each rim circle reaches
          // +- r sqrt(1 - a_z^2) in z.
          const double az = std::clamp(X.linear()(2, 2), -1.0, 1.0);
          const double h = 0.5 * g.length_m * std::abs(az) + g.radius_m * std::sqrt(1 - az * az);
          span(cz - h, cz + h);
          break;
        }
        case Geometry::Kind::Mesh:
          if (!g.mesh) break;
          for (const Eigen::Vector3f& v : g.mesh->vertices) {
            const double z = (X * v.cast<double>()).z();
            span(z, z);
          }
          break;
      }
    }
  }
  s.height_m = hi >= lo ? hi - lo : 0.0;
  return s;
}

}  // namespace dmbd::model
