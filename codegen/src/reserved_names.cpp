// The names a signal of generated code cannot take (reserved_names.hpp).
#include "reserved_names.hpp"

#include <cctype>
#include <set>
#include <string>

#include "dmbd/blocks/error.hpp"
#include "emit_common.hpp"

namespace dmbd::codegen::detail {

namespace {

bool is_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

const std::set<std::string>& c_keywords() {
  static const std::set<std::string> k{
      "auto",   "break",    "case",     "char",   "const",  "continue", "default",  "do",       "double",
      "else",   "enum",     "extern",   "float",  "for",    "goto",     "if",       "inline",   "int",
      "long",   "register", "restrict", "return", "short",  "signed",   "sizeof",   "static",   "struct",
      "switch", "typedef",  "union",    "unsigned", "void", "volatile", "while",    "_Bool",    "_Complex",
      "_Imaginary"};
  return k;
}

const std::set<std::string>& cpp_keywords() {
  static const std::set<std::string> k{
      "alignas",   "alignof",      "and",        "and_eq",       "asm",          "auto",      "bitand",    "bitor",
      "bool",      "break",        "case",       "catch",        "char",         "char16_t",  "char32_t",  "class",
      "compl",     "const",        "constexpr",  "const_cast",   "continue",     "decltype",  "default",   "delete",
      "do",        "double",       "dynamic_cast", "else",       "enum",         "explicit",  "export",    "extern",
      "false",     "float",        "for",        "friend",       "goto",         "if",        "inline",    "int",
      "long",      "mutable",      "namespace",  "new",          "noexcept",     "not",       "not_eq",    "nullptr",
      "operator",  "or",           "or_eq",      "private",      "protected",    "public",    "register",  "reinterpret_cast",
      "return",    "short",        "signed",     "sizeof",       "static",       "static_assert", "static_cast", "struct",
      "switch",    "template",     "this",       "thread_local", "throw",        "true",      "try",       "typedef",
      "typeid",    "typename",     "union",      "unsigned",     "using",        "virtual",   "void",      "volatile",
      "wchar_t",   "while",        "xor",        "xor_eq"};
  return k;
}

// The rule itself: `keywords` of `language`, and `used` (listed in the message as `listed`).
void check(const LoopProgram& p, const std::string& language, const std::set<std::string>& keywords,
           const std::set<std::string>& used, const std::string& listed) {
  if (!is_identifier(p.name)) throw InputError("program name '" + p.name + "': expected a " + language + " identifier");
  for (const Slot& s : p.slots) {
    if (s.kind == SlotKind::State) continue;  // a member: self->name_ (C), name_ (C++)
    if (keywords.count(s.name) || used.count(s.name))
      throw InputError("signal '" + s.name + "' (" + s.origin + "): " +
                       (keywords.count(s.name) ? "a " + language + " keyword" : "a name the generated " + language + " code uses (" + listed + ")") +
                       " cannot name a signal of " + language + " output; rename it in the diagram");
  }
}

}  // namespace

void check_c_names(const LoopProgram& p) { check(p, "C", c_keywords(), {"self", "u", "y", "acc"}, "self, u, y, acc"); }

void check_cpp_names(const LoopProgram& p) {
  std::set<std::string> used{"u", "y", "acc", "fx", "status_"};
  for (const Slot& s : p.slots)
    if (s.kind == SlotKind::State) used.insert(state_member(s));
  if (cpp_keywords().count(p.name)) throw InputError("program name '" + p.name + "': a C++ keyword cannot name a namespace");
  check(p, "C++", cpp_keywords(), used, "u, y, acc, fx, status_ and the states' members NAME_");
}

}  // namespace dmbd::codegen::detail
