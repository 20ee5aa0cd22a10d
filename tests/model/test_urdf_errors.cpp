// Bad URDFs: every case throws a ModelError whose one-line message starts with
// "FILE:LINE: " (the line found in the fixture by a marker, not hard-coded), names
// the element and says what was expected. Fixtures: tests/model/data/urdf/bad/.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "test_urdf_support.hpp"

namespace dmbd::model {
namespace {

using test::expect_model_error;
using test::line_of;
using test::slurp;
using test::urdf_data;

struct BadFile {
  std::string file;                    // under urdf/bad/
  std::string marker;                  // text on the line the message must name
  std::vector<std::string> fragments;  // further text the message must hold
  bool strict = false;                 // loaded with UrdfOptions::strict (what is otherwise repaired)
};

// The case as ctest lists it (gtest would print the struct's bytes, pointers included).
void PrintTo(const BadFile& c, std::ostream* os) { *os << c.file << (c.strict ? " (strict)" : ""); }

class UrdfBadFile : public testing::TestWithParam<BadFile> {};

TEST_P(UrdfBadFile, OneLineWithFileLineAndElement) {
  const BadFile& c = GetParam();
  const std::string path = urdf_data("bad/" + c.file);
  const int line = line_of(slurp(path), c.marker);
  ASSERT_GT(line, 0) << "marker not in the fixture: " << c.marker;
  UrdfOptions o;
  o.strict = c.strict;
  const std::string msg = expect_model_error([&] { load_urdf(path, o); }, c.fragments);
  EXPECT_EQ(msg.rfind(path + ":" + std::to_string(line) + ": ", 0), 0u) << msg;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, UrdfBadFile,
    testing::Values(
        BadFile{"malformed.urdf", "</inertia>", {"malformed XML"}},
        BadFile{"no_robot.urdf", "<model", {"<model>", "expected <robot"}},
        BadFile{"unknown_link.urdf", "<joint name=\"hip\"", {"joint 'hip'", "child link 'thig' is not defined"}},
        BadFile{"two_parents.urdf",
                "<joint name=\"knee_linkage\"",
                {"joint 'knee_linkage'", "link 'shank' already has the parent joint 'knee' (line 10)", "tree"}},
        BadFile{"loop.urdf",
                "<joint name=\"c_to_a\"",
                {"joint 'c_to_a'", "loop in the kinematic tree: bar_b -> bar_c -> bar_a -> bar_b", "root 'pelvis'"}},
        BadFile{"two_roots.urdf",
                "<link name=\"camera_frame\"",
                {"link 'camera_frame'", "a second root", "link 'pelvis' at line 3", "expected one root"}},
        BadFile{"nan_origin.urdf", "xyz=\"0 nan", {"joint 'hip'", "<origin xyz=\"0 nan 0.1\">", "'nan' is not a finite number"}},
        BadFile{"inf_inertia.urdf", "iyy=\"inf\"", {"link 'thigh'", "<inertia iyy=\"inf\">", "'inf' is not a finite number"}},
        BadFile{"negative_mass.urdf", "<mass", {"link 'thigh'", "mass -2 kg is negative", "expected >= 0"}},
        BadFile{"not_positive_definite.urdf",
                "<inertia ",
                {"link 'thigh'", "inertia is not positive definite", "principal moments -0.01, 0.01, 0.03", "expected all > 0"}},
        BadFile{"triangle_inequality.urdf",
                "<inertia ",
                {"link 'thigh'", "triangle inequality", "0.01 + 0.01 < 0.05", "expected each <= the sum of the other two",
                 "strict: not repaired by balanceinertia"},
                true},
        BadFile{"revolute_without_limit.urdf",
                "<joint name=\"hip_pitch\"",
                {"joint 'hip_pitch'", "a revolute joint needs <limit", "type=\"continuous\""}},
        BadFile{"unknown_joint_type.urdf",
                "<joint name=\"hip\"",
                {"joint 'hip'", "unknown type 'ball'", "expected fixed, revolute, continuous, prismatic, floating or planar"}},
        BadFile{"zero_axis.urdf", "<axis", {"joint 'hip'", "the axis is zero"}}),
    [](const testing::TestParamInfo<BadFile>& i) {
      std::string n = i.param.file.substr(0, i.param.file.find('.'));
      return n;
    });

TEST(UrdfBadInput, MissingFile) {
  const std::string path = urdf_data("bad/no_such_file.urdf");
  const std::string msg = expect_model_error([&] { load_urdf(path); }, {"cannot open the file", "No such file"});
  EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
}

TEST(UrdfBadInput, Folder) {
  expect_model_error([&] { load_urdf(urdf_data("bad")); }, {urdf_data("bad") + ": is a folder"});
}

// A binary file is named as not text at its first wrong byte, which is never printed.
TEST(UrdfBadInput, BinaryFileIsNotText) {
  const std::string path = (std::filesystem::temp_directory_path() / ("dmbd_binary_" + std::to_string(::getpid()) + ".urdf")).string();
  std::ofstream(path, std::ios::binary) << std::string("<robot>\n\x7f" "ELF\x02\x01\0", 14);
  const std::string msg = expect_model_error([&] { load_urdf(path); }, {path + ":2:1: the file is not text: byte 9 is 0x7F"});
  EXPECT_TRUE(std::all_of(msg.begin(), msg.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x20 && c != 0x7f; })) << msg;
  std::filesystem::remove(path);
}

// Text cases: the line is that of the marker in the text.
struct BadText {
  std::string name, xml, marker;
  std::vector<std::string> fragments;
};

void PrintTo(const BadText& c, std::ostream* os) { *os << c.name; }

class UrdfBadText : public testing::TestWithParam<BadText> {};

TEST_P(UrdfBadText, OneLineWithLabelLineAndElement) {
  const BadText& c = GetParam();
  const int line = c.marker.empty() ? 1 : line_of(c.xml, c.marker);
  ASSERT_GT(line, 0) << "marker not in the text: " << c.marker;
  const std::string msg = expect_model_error([&] { parse_urdf(c.xml, ".", "inline.urdf"); }, c.fragments);
  EXPECT_EQ(msg.rfind("inline.urdf:" + std::to_string(line) + ": ", 0), 0u) << msg;
}

const std::string kTwoLinks = "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n";
std::string with_joint(const std::string& joint) { return kTwoLinks + joint + "\n</robot>\n"; }
std::string with_link(const std::string& body) { return "<robot name=\"r\">\n<link name=\"l\">\n" + body + "\n</link>\n</robot>\n"; }
const std::string kInertia = "<inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/>";

INSTANTIATE_TEST_SUITE_P(
    Cases, UrdfBadText,
    testing::Values(
        BadText{"Empty", "", "", {"malformed XML"}},
        BadText{"NoElement", "<?xml version=\"1.0\"?>\n", "", {"no <robot> element"}},
        BadText{"RobotWithoutName", "<robot>\n<link name=\"a\"/>\n</robot>", "<robot", {"<robot> has no name"}},
        BadText{"NoLinks", "<robot name=\"r\">\n</robot>", "<robot", {"robot 'r'", "no <link>"}},
        BadText{"DuplicateLink", "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"a\"/>\n</robot>", "<link name=\"a\"/>\n</",
                {"link 'a'", "a second link of that name (the first is at line 2)"}},
        BadText{"DuplicateJoint",
                kTwoLinks + "<link name=\"c\"/>\n<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>\n"
                            "<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"c\"/></joint>\n</robot>",
                "<child link=\"c\"", {"joint 'j'", "a second joint of that name (the first is at line 5)"}},
        BadText{"UndefinedParent", with_joint("<joint name=\"j\" type=\"fixed\"><parent link=\"x\"/><child link=\"b\"/></joint>"),
                "<joint", {"joint 'j'", "parent link 'x' is not defined"}},
        BadText{"NoChild", with_joint("<joint name=\"j\" type=\"fixed\">\n<parent link=\"a\"/>\n</joint>"), "<joint",
                {"joint 'j'", "no <child link="}},
        BadText{"SelfLoop", with_joint("<joint name=\"j\" type=\"fixed\"><parent link=\"b\"/><child link=\"b\"/></joint>"),
                "<joint", {"joint 'j'", "parent and child are the same link 'b'"}},
        BadText{"LoopWithoutRoot",
                kTwoLinks + "<joint name=\"ab\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>\n"
                            "<joint name=\"ba\" type=\"fixed\"><parent link=\"b\"/><child link=\"a\"/></joint>\n</robot>",
                "<joint name=\"ba\"", {"joint 'ba'", "loop in the kinematic tree", "no link is the root"}},
        BadText{"PrismaticWithoutLimit",
                with_joint("<joint name=\"slide\" type=\"prismatic\"><parent link=\"a\"/><child link=\"b\"/></joint>"), "<joint",
                {"joint 'slide'", "a prismatic joint needs <limit"}},
        BadText{"LimitWithoutEffort",
                with_joint("<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n"
                           "<limit lower=\"0\" upper=\"1\" velocity=\"1\"/></joint>"),
                "<limit", {"joint 'j'", "<limit> has no effort attribute"}},
        BadText{"LowerAboveUpper",
                with_joint("<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n"
                           "<limit lower=\"1\" upper=\"-1\" effort=\"1\" velocity=\"1\"/></joint>"),
                "<limit", {"joint 'j'", "lower is above upper"}},
        BadText{"NegativeEffort",
                with_joint("<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/>\n"
                           "<limit effort=\"-3\" velocity=\"1\"/></joint>"),
                "<limit", {"joint 'j'", "<limit effort=\"-3\">", "expected a value >= 0 N m"}},
        BadText{"NegativeDamping",
                with_joint("<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/>\n"
                           "<dynamics damping=\"-0.1\"/></joint>"),
                "<dynamics", {"joint 'j'", "<dynamics damping=\"-0.1\">", "expected a value >= 0"}},
        BadText{"MissingType", with_joint("<joint name=\"j\"><parent link=\"a\"/><child link=\"b\"/></joint>"), "<joint",
                {"joint 'j'", "no type attribute"}},
        BadText{"OutOfRangeNumber",
                with_joint("<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/>\n<origin xyz=\"0 0 1e999\"/></joint>"),
                "<origin", {"joint 'j'", "'1e999' is out of the range of a double"}},
        BadText{"TwoNumbersForThree",
                with_joint("<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/>\n<origin rpy=\"0 1\"/></joint>"),
                "<origin", {"joint 'j'", "<origin rpy=\"0 1\">", "expected 3 numbers, found 2"}},
        BadText{"NotANumber",
                with_joint("<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/>\n<axis xyz=\"0 one 0\"/></joint>"),
                "<axis", {"joint 'j'", "'one' is not a number"}},
        BadText{"InertialWithoutMass", with_link("<inertial>\n" + kInertia + "\n</inertial>"), "<inertial>",
                {"link 'l'", "<inertial> has no <mass"}},
        BadText{"InertialWithoutInertia", with_link("<inertial>\n<mass value=\"1\"/>\n</inertial>"), "<inertial>",
                {"link 'l'", "<inertial> has no <inertia"}},
        BadText{"TwoInertials",
                with_link("<inertial><mass value=\"1\"/>" + kInertia + "</inertial>\n<inertial><mass value=\"2\"/>" + kInertia +
                          "</inertial>"),
                "<inertial><mass value=\"2\"", {"link 'l'", "a second <inertial> in <link> (line 3 has the first"}},
        BadText{"NaNMass", with_link("<inertial>\n<mass value=\"NaN\"/>\n" + kInertia + "\n</inertial>"), "<mass",
                {"link 'l'", "'NaN' is not a finite number"}},
        BadText{"NegativeMassZeroInertiaIsStillNegative",
                with_link("<inertial>\n<mass value=\"-0.5\"/>\n<inertia ixx=\"0\" ixy=\"0\" ixz=\"0\" iyy=\"0\" iyz=\"0\" izz=\"0\"/>\n</inertial>"),
                "<mass", {"link 'l'", "mass -0.5 kg is negative"}},
        BadText{"PointMassIsNotPositiveDefinite",
                with_link("<inertial>\n<mass value=\"0.1\"/>\n<inertia ixx=\"0\" ixy=\"0\" ixz=\"0\" iyy=\"0\" iyz=\"0\" izz=\"0\"/>\n</inertial>"),
                "<inertia ", {"link 'l'", "inertia is not positive definite", "mass 0.1 kg"}},
        BadText{"MasslessWithNegativeInertia",
                with_link("<inertial>\n<mass value=\"0\"/>\n<inertia ixx=\"-1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/>\n</inertial>"),
                "<inertia ", {"link 'l'", "not positive semi-definite"}},
        BadText{"CapsuleGeometry", with_link("<collision>\n<geometry>\n<capsule radius=\"0.1\" length=\"0.3\"/>\n</geometry>\n</collision>"),
                "<capsule", {"link 'l'", "<capsule> is not a URDF geometry", "expected <box>, <cylinder>, <sphere> or <mesh>"}},
        BadText{"EmptyGeometry", with_link("<visual>\n<geometry>\n</geometry>\n</visual>"), "<geometry>",
                {"link 'l'", "<geometry> is empty"}},
        BadText{"VisualWithoutGeometry", with_link("<visual>\n<origin xyz=\"0 0 0\"/>\n</visual>"), "<visual>",
                {"link 'l'", "<visual> has no <geometry>"}},
        BadText{"MeshWithoutFilename", with_link("<visual>\n<geometry>\n<mesh scale=\"1 1 1\"/>\n</geometry>\n</visual>"), "<mesh",
                {"link 'l'", "<mesh> has no filename attribute"}},
        BadText{"NegativeBox", with_link("<visual>\n<geometry>\n<box size=\"1 -1 1\"/>\n</geometry>\n</visual>"), "<box",
                {"link 'l'", "<box size=\"1 -1 1\">", "expected sizes >= 0 m"}},
        BadText{"CylinderWithoutLength", with_link("<visual>\n<geometry>\n<cylinder radius=\"1\"/>\n</geometry>\n</visual>"),
                "<cylinder", {"link 'l'", "<cylinder> has no length attribute"}},
        BadText{"ColorOutOfRange",
                with_link("<visual>\n<geometry><sphere radius=\"1\"/></geometry>\n<material name=\"m\">\n<color rgba=\"1 0 0 2\"/>\n</material>\n</visual>"),
                "<color", {"link 'l'", "expected 4 numbers in [0, 1]"}},
        BadText{"UrdfdomOnlyError", "<robot name=\"r\" version=\"2.0\">\n<link name=\"a\"/>\n</robot>", "<robot",
                {"urdfdom:", "version"}},
        // Issue 13 item 12: TinyXML reads past the end of the text on a UTF-8 sequence cut
        // short (the fuzzer's unreproducible memcpy overflows); such text is refused first.
        BadText{"Utf8CutShortAtTheEnd", "<robot name=\"r\">\n<link name=\"a\"/>\n</robot>\n\xF0\x9F", "\xF0",
                {"column 1: byte 0xF0 is not UTF-8 text (expected a UTF-8 file)"}},
        BadText{"Utf8CutShortInAName", "<robot name=\"r\">\n<link name=\"a\xE2\x82\"/>\n</robot>", "<link",
                {"column 14: byte 0xE2 is not UTF-8 text"}},
        BadText{"Latin1", "<robot name=\"r\xE9\">\n<link name=\"a\"/>\n</robot>", "<robot", {"column 15: byte 0xE9 is not UTF-8"}},
        BadText{"NulByte", std::string("<robot name=\"r\">\n<link name=\"a\"/>") + '\0' + "\n</robot>", "<link",
                {"column 17: a NUL byte (expected XML text)"}},
        BadText{"DeepNesting", "<robot name=\"r\">\n" + [] {
                  std::string s;
                  for (int k = 0; k < 100000; ++k) s += "<a>";  // used to overflow the stack in TinyXML
                  return s;
                }(), "<a>", {"column 29998: more than 10000 elements with content"}}),
    [](const testing::TestParamInfo<BadText>& i) { return i.param.name; });

TEST(UrdfText, Utf8AndManyEmptyElementsAreAccepted) {
  // Non-ASCII names and comments in UTF-8 load; self-closing elements (even 20,000 of
  // them, ignored with one warning) do not count towards the limit of 10,000 with content.
  std::string xml = "<robot name=\"r\xC3\xA9\">\n<!-- \xF0\x9F\xA6\xBF -->\n<link name=\"\xE2\x82\xAC\"/>\n";
  for (int k = 0; k < 20000; ++k) xml += "<extra note=\"/>\"/>";
  xml += "\n</robot>\n";
  const RobotDescription r = parse_urdf(xml, ".", "inline.urdf");
  EXPECT_EQ(r.name, "r\xC3\xA9");
  ASSERT_EQ(r.links.size(), 1u);
  EXPECT_EQ(r.links[0].name, "\xE2\x82\xAC");
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("20000 elements"), std::string::npos) << r.warnings[0];
}

}  // namespace
}  // namespace dmbd::model
