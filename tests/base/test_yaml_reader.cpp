// The located YAML reader: every problem recorded at its file:line:column with what
// was expected, all of them rather than the first; numbers through the parser supplied
// from above; unknown and repeated keys; tabs and bytes that are not text named as such.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dmbd/base/yaml_reader.hpp"

namespace {

using dmbd::yaml::Reader;

std::vector<std::string> lines(const Reader& rd) {
  std::vector<std::string> out;
  for (const auto& d : rd.diagnostics()) out.push_back(d.where.str() + ": " + d.message);
  return out;
}

TEST(YamlReader, UnknownAndRepeatedKeysAreEachReportedAtTheirPlace) {
  Reader rd("f.yaml");
  const YAML::Node root = rd.parse("a: 1\nbee: 2\na: 3\nc: 4\n");
  EXPECT_FALSE(rd.keys(root, {"a"}, "top"));
  EXPECT_EQ(lines(rd), (std::vector<std::string>{"f.yaml:2:1: top: unknown key 'bee' (expected one of: a)",
                                                 "f.yaml:3:1: top: key 'a' is given twice",
                                                 "f.yaml:4:1: top: unknown key 'c' (expected one of: a)"}));
  Reader ok("g.yaml");
  EXPECT_TRUE(ok.keys(ok.parse("a: 1\n"), {"a", "b"}, ""));
  EXPECT_FALSE(ok.failed());
}

TEST(YamlReader, PlainNumbersByDefaultAndTheSuppliedParserOtherwise) {
  Reader plain("f.yaml");
  const YAML::Node root = plain.parse("rate: 2*1000\nx: 1.5e3\n");
  EXPECT_EQ(plain.number(root["x"], "x"), 1500.0);
  EXPECT_THROW(plain.number(root["rate"], "rate"), dmbd::yaml::Skip);
  EXPECT_EQ(lines(plain), std::vector<std::string>{"f.yaml:1:7: rate: expected a number, got '2*1000'"});
  // A parser from above: its column is added to the scalar's.
  Reader product("f.yaml", [](const std::string& text) {
    const auto star = text.find('*');
    if (star == std::string::npos) throw dmbd::NumberError(1, "no product");
    return std::stod(text.substr(0, star)) * std::stod(text.substr(star + 1));
  });
  const YAML::Node r2 = product.parse("rate: 2*1000\nbad: 7\n");
  EXPECT_EQ(product.number(r2["rate"], "rate"), 2000.0);
  EXPECT_THROW(product.number(r2["bad"], "bad"), dmbd::yaml::Skip);
  EXPECT_EQ(lines(product), std::vector<std::string>{"f.yaml:2:6: bad: no product"});
}

TEST(YamlReader, RangesAreCheckedAtTheValuesLine) {
  Reader rd("f.yaml");
  const YAML::Node root = rd.parse("w: 17\nbig: 1e300\nhalf: 2.5\nd: 1e12\nneg: -1\ninf: 1e999\n");
  EXPECT_EQ(rd.integer(root["w"], "w", 16, 32), 17);
  EXPECT_FALSE(rd.guard([&] { rd.integer(root["big"], "big", 16, 32); }));
  EXPECT_FALSE(rd.guard([&] { rd.integer(root["half"], "half", 0, 10); }));
  EXPECT_FALSE(rd.guard([&] { rd.number_in(root["d"], "d", 0, 1e9, "s"); }));
  EXPECT_FALSE(rd.guard([&] { rd.positive(root["neg"], "neg"); }));
  EXPECT_FALSE(rd.guard([&] { rd.number(root["inf"], "inf"); }));
  EXPECT_EQ(lines(rd), (std::vector<std::string>{"f.yaml:2:6: big: expected a whole number from 16 to 32",
                                                 "f.yaml:3:7: half: expected a whole number from 0 to 10",
                                                 "f.yaml:4:4: d: expected a number from 0 to 1e+09 s, got 1e+12 s",
                                                 "f.yaml:5:6: neg: expected a positive number, got -1",
                                                 "f.yaml:6:6: inf: expected a finite number, got '1e999'"}));
}

TEST(YamlReader, GuardCollectsEveryProblemAndEachOnce) {
  Reader rd("f.yaml");
  const YAML::Node root = rd.parse("a: x\nb: y\nc: 3\n");
  double sum = 0;
  for (int pass = 0; pass < 2; ++pass)  // a value read twice is reported once
    for (const char* k : {"a", "b", "c"}) rd.guard([&] { sum += rd.number(root[k], k); });
  EXPECT_EQ(sum, 6.0);
  EXPECT_EQ(rd.diagnostics().size(), 2u);
  EXPECT_EQ(rd.diagnostics()[1].where.line, 2);
}

TEST(YamlReader, MissingValuesAndWrongKindsAreLocated) {
  Reader rd("f.yaml");
  const YAML::Node root = rd.parse("m: {a: 1}\nl:\n[1]: 2\n");
  EXPECT_FALSE(rd.guard([&] { rd.number(root["m"], "m"); }));
  EXPECT_FALSE(rd.guard([&] { rd.number(root["nothing"], "nothing"); }));
  EXPECT_FALSE(rd.guard([&] { rd.list(root, "l", "l"); }));  // empty: at its key
  EXPECT_FALSE(rd.guard([&] { rd.text(root["m"], "m"); }));
  EXPECT_FALSE(rd.keys(root, {"m", "l"}, "top"));  // recorded, reading goes on
  EXPECT_EQ(lines(rd), (std::vector<std::string>{"f.yaml:1:4: m: expected a number", "f.yaml: nothing: expected a number",
                                                 "f.yaml:2:1: l: expected a list", "f.yaml:1:4: m: expected a string",
                                                 "f.yaml:3:1: top: a key must be a name, not a list, a map or empty"}));
}

TEST(YamlReader, ATabInTheIndentationIsNamed) {
  struct Case {
    std::string text;
    int line, column;
  };
  for (const Case& c : {Case{"a:\n\tb: 1\n", 2, 1}, Case{"a:\n  b: 1\n\tc: 2\n", 3, 1}, Case{"a: 1\n  \tb: 2\n", 2, 3},
                        Case{"a: 1\n\t\n", 2, 1}, Case{"a:\n  - 1\n\t- 2\n", 3, 1}}) {
    Reader rd("f.yaml");
    EXPECT_FALSE(rd.guard([&] { rd.parse(c.text); })) << c.text;
    ASSERT_EQ(rd.diagnostics().size(), 1u);
    const auto& d = rd.diagnostics()[0];
    EXPECT_NE(d.message.find("tabs are not allowed"), std::string::npos) << d.message;
    EXPECT_EQ(d.message.find("illegal"), std::string::npos) << d.message;
    EXPECT_EQ(d.where.line, c.line) << c.text;
    EXPECT_EQ(d.where.column, c.column) << c.text;
  }
  // Tabs that YAML allows (inside a flow list, after a key) are not errors.
  Reader rd("f.yaml");
  const YAML::Node root = rd.parse("a: [1,\n\t2]\nb:\t3\n");
  EXPECT_EQ(root["a"].size(), 2u);
  EXPECT_EQ(rd.number(root["b"], "b"), 3.0);
}

TEST(YamlReader, MalformedYamlAndBinaryAreLocated) {
  Reader rd("f.yaml");
  EXPECT_FALSE(rd.guard([&] { rd.parse("a: [1, 2}\n"); }));
  ASSERT_EQ(rd.diagnostics().size(), 1u);
  EXPECT_EQ(rd.diagnostics()[0].where.line, 1);
  EXPECT_EQ(rd.diagnostics()[0].message.rfind("malformed YAML: ", 0), 0u);
  Reader bin("f.bin");
  EXPECT_FALSE(bin.guard([&] { bin.parse(std::string("ELF\0\0\x01", 6)); }));
  EXPECT_EQ(lines(bin), std::vector<std::string>{
                            "f.bin:1:4: the file is not text: byte 4 is 0x00, a control character (expected a UTF-8 text file)"});
}

TEST(YamlReader, BooleansAndLongScalarsInMessages) {
  Reader rd("f.yaml");
  const YAML::Node root = rd.parse("t: true\nf: off\nx: maybe\nlong: " + std::string(200, 'z') + "\n");
  EXPECT_TRUE(rd.boolean(root["t"], "t"));
  EXPECT_FALSE(rd.boolean(root["f"], "f"));
  EXPECT_FALSE(rd.guard([&] { rd.boolean(root["x"], "x"); }));
  EXPECT_FALSE(rd.guard([&] { rd.number(root["long"], "long"); }));
  ASSERT_EQ(rd.diagnostics().size(), 2u);
  EXPECT_EQ(rd.diagnostics()[0].message, "x: expected true or false, got 'maybe'");
  EXPECT_LT(rd.diagnostics()[1].message.size(), 100u) << "a long scalar is cut short";
}

}  // namespace
