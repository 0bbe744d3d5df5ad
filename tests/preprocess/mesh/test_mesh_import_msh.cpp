// Gmsh MSH files (preprocess/mesh/mesh_import.hpp, read_mesh_msh): ASCII 2.2 and 4.1 with
// non-contiguous node tags, physical groups as labels and node tags; every file adamss cannot run
// is an InputError naming the file and the line.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "support/scratch.hpp"

using namespace adamss::preprocess;
namespace fs = std::filesystem;

namespace {

fs::path write_file(const std::string& name, const std::string& text) {
  return adamss::test::write_scratch_file("adamss_test_import_msh", name, text);
}

// Two unit-mm hexahedra side by side along x (nodes 101..112, x = 0, 1, 2 mm), physical volumes
// 1 "myocardium" and 2 "scar", the quad at x = 0 in surface group 10 "left", a point group 20
// without a name, and node 999 used by no element.
const char* kHex22 = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
2 10 "left"
3 1 "myocardium"
3 2 "scar"
$EndPhysicalNames
$Nodes
13
101 0 0 0
102 0.001 0 0
103 0.001 0.001 0
104 0 0.001 0
105 0 0 0.001
106 0.001 0 0.001
107 0.001 0.001 0.001
108 0 0.001 0.001
109 0.002 0 0
110 0.002 0.001 0
111 0.002 0 0.001
112 0.002 0.001 0.001
999 5 5 5
$EndNodes
$Elements
4
1 15 2 20 1 101
2 3 2 10 3 101 104 108 105
3 5 2 1 1 101 102 103 104 105 106 107 108
4 5 2 2 2 102 109 110 103 106 111 112 107
$EndElements
)";

// The same two tetrahedra as the .vtu tests (nodes 1..5) in format 4.1 with $Entities: volume 1 in
// physical group 5 "wall", volume 2 without a group (label = its entity tag, 2), and triangle
// surface 3 in group 7 "base".
const char* kTet41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 7 "base"
3 5 "wall"
$EndPhysicalNames
$Entities
0 0 1 2
3 0 0 0 0.001 0.001 0 1 7 0
1 0 0 0 0.001 0.001 0.001 1 5 0
2 0 0 0 0.001 0.001 0.001 0 0
$EndEntities
$Nodes
3 5 1 5
2 3 0 3
1
2
3
0 0 0
0.001 0 0
0 0.001 0
3 1 0 1
4
0 0 0.001
3 2 0 1
5
0.000333333333333 0.001 0.001
$EndNodes
$Elements
3 3 1 3
2 3 2 1
1 1 2 3
3 1 4 1
2 1 2 3 4
3 2 4 1
3 2 5 3 4
$EndElements
)";

}  // namespace

TEST(MeshImportMsh, Format22HexahedraWithGroups) {
  const Mesh m = read_mesh_file(write_file("hex22.msh", kHex22));
  EXPECT_EQ(m.type, ElementType::Hex8);
  ASSERT_EQ(m.element_count(), 2u);
  ASSERT_EQ(m.node_count(), 12u) << "node 999 belongs to no element";
  EXPECT_EQ(m.labels, (std::vector<std::int32_t>{1, 2}));
  EXPECT_EQ(m.attributes.at("label_names"), "1=myocardium,2=scar");
  // Nodes in order of first use: 101..108 are 0..7, so element 0 is 0..7 and keeps its coordinates.
  for (int a = 0; a < 8; ++a) EXPECT_EQ(m.element(0)[a], a);
  EXPECT_DOUBLE_EQ(m.nodes(0, m.element(1)[1]), 0.002);  // node 109
  ASSERT_EQ(m.node_tags.count("left"), 1u);
  const std::set<Index> left(m.node_tags.at("left").begin(), m.node_tags.at("left").end());
  EXPECT_EQ(left, (std::set<Index>{0, 3, 4, 7}));
  for (const Index n : left) EXPECT_DOUBLE_EQ(m.nodes(0, n), 0.0);
  ASSERT_EQ(m.node_tags.count("physical_0_20"), 1u);
  EXPECT_EQ(m.node_tags.at("physical_0_20"), std::vector<Index>{0});
  EXPECT_FALSE(m.has_fibres());
}

TEST(MeshImportMsh, Format41TetrahedraWithEntities) {
  const Mesh m = read_mesh_file(write_file("tet41.msh", kTet41));
  EXPECT_EQ(m.type, ElementType::Tet4);
  ASSERT_EQ(m.element_count(), 2u);
  ASSERT_EQ(m.node_count(), 5u);
  EXPECT_EQ(m.labels, (std::vector<std::int32_t>{5, 2})) << "group 5, then entity 2 (no group)";
  EXPECT_EQ(m.attributes.at("label_names"), "5=wall");
  EXPECT_EQ(m.connectivity, (std::vector<Index>{0, 1, 2, 3, 1, 4, 2, 3}));
  EXPECT_DOUBLE_EQ(m.nodes(2, 3), 0.001);
  ASSERT_EQ(m.node_tags.count("base"), 1u);
  EXPECT_EQ(m.node_tags.at("base"), (std::vector<Index>{0, 1, 2}));
}

TEST(MeshImportMsh, RefusesWhatCannotBeRunWithTheFileAndLine) {
  const std::string hex = kHex22;
  const auto expect_error = [](const std::string& name, const std::string& text, const std::string& what) {
    SCOPED_TRACE(name);
    const fs::path p = write_file(name + ".msh", text);
    try {
      (void)read_mesh_file(p);
      ADD_FAILURE() << "no error";
    } catch (const adamss::InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
  };
  const auto edit = [&](const std::string& from, const std::string& to) {
    std::string t = hex;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  expect_error("binary", edit("2.2 0 8", "2.2 1 8"), "line 2: a binary MSH file");
  expect_error("version", edit("2.2 0 8", "3 0 8"), "MSH format 3; adamss reads 2.2 and 4.1");
  expect_error("not_msh", "solid cube\nfacet normal 0 0 1\n", "line 1: not a gmsh MSH file");
  expect_error("empty", "", "empty file");
  expect_error("second_order", edit("3 5 2 1 1 101", "3 11 2 1 1 101"), "gmsh type 11");
  expect_error("mixed", edit("4 5 2 2 2 102 109 110 103 106 111 112 107", "4 4 2 2 2 102 109 110 106"),
               "both tetrahedra and hexahedra");
  expect_error("surface_only",
               edit("3 5 2 1 1 101 102 103 104 105 106 107 108\n4 5 2 2 2 102 109 110 103 106 111 112 107\n",
                    "3 2 2 10 3 101 102 103\n4 2 2 10 3 101 103 104\n"),
               "no tetrahedra or hexahedra");
  expect_error("undefined_node", edit("4 5 2 2 2 102 109", "4 5 2 2 2 102 777"), "uses node 777, not in $Nodes");
  expect_error("duplicate_node",
               edit("102 0.001 0 0\n", "102 0.001 0 0\n102 0.001 0 0\n").replace(hex.find("13\n101"), 2, "14"),
               "node 102 is defined twice");
  expect_error("nan", edit("102 0.001 0 0", "102 nan 0 0"), "");
  expect_error("inverted",
               edit("3 5 2 1 1 101 102 103 104 105 106 107 108", "3 5 2 1 1 105 106 107 108 101 102 103 104"),
               "element 0 is inverted");
  expect_error("truncated", hex.substr(0, hex.find("$EndNodes")), "line");
  expect_error("no_elements", hex.substr(0, hex.find("$Elements")), "no $Nodes or no $Elements");
}
