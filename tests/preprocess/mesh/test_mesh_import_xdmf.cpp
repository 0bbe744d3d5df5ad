// XDMF meshes (preprocess/mesh/mesh_import.hpp, read_mesh_xdmf) with inline XML data items: two
// tetrahedra with labels, a fibre frame and a cell field; a time series' first grid; every file
// adamss cannot run is an InputError naming the file. (HDF5 data items: ctest python.xdmf reads
// adamss's sidecars and meshio's files.)
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "support/scratch.hpp"

using namespace adamss::preprocess;
namespace fs = std::filesystem;

namespace {

fs::path write_file(const std::string& name, const std::string& text) {
  return adamss::test::write_scratch_file("adamss_test_import_xdmf", name, text);
}

// The two tetrahedra of the .vtu tests, labels 1 and 7 as gmsh:physical, fibre z, sheet x, scar.
const std::string kTets = R"(<?xml version="1.0"?>
<Xdmf Version="3.0">
  <Domain>
    <Grid Name="Grid" GridType="Uniform">
      <Geometry GeometryType="XYZ">
        <DataItem DataType="Float" Dimensions="5 3" Format="XML" Precision="8">
          0 0 0  0.001 0 0  0 0.001 0  0 0 0.001  0.000333333333333 0.001 0.001
        </DataItem>
      </Geometry>
      <Topology TopologyType="Tetrahedron" NumberOfElements="2" NodesPerElement="4">
        <DataItem DataType="Int" Dimensions="2 4" Format="XML" Precision="8">0 1 2 3 1 4 2 3</DataItem>
      </Topology>
      <Attribute Name="gmsh:physical" AttributeType="Scalar" Center="Cell">
        <DataItem DataType="Int" Dimensions="2" Format="XML">1 7</DataItem>
      </Attribute>
      <Attribute Name="fiber" AttributeType="Vector" Center="Cell">
        <DataItem DataType="Float" Dimensions="2 3" Format="XML">0 0 1 0 0 1</DataItem>
      </Attribute>
      <Attribute Name="sheet" AttributeType="Vector" Center="Cell">
        <DataItem DataType="Float" Dimensions="2 3" Format="XML">1 0 0 1 0 0</DataItem>
      </Attribute>
      <Attribute Name="scar" AttributeType="Scalar" Center="Cell">
        <DataItem DataType="Float" Dimensions="2" Format="XML">0.25 1</DataItem>
      </Attribute>
      <Attribute Name="u" AttributeType="Vector" Center="Node">
        <DataItem DataType="Float" Dimensions="5 3" Format="XML">0 0 0 0 0 0 0 0 0 0 0 0 0 0 0</DataItem>
      </Attribute>
    </Grid>
  </Domain>
</Xdmf>
)";

std::string edit(const std::string& from, const std::string& to) {
  std::string t = kTets;
  t.replace(t.find(from), from.size(), to);
  return t;
}

}  // namespace

TEST(MeshImportXdmf, InlineTetrahedraWithLabelsFibresAndFields) {
  const Mesh m = read_mesh_file(write_file("tets.xdmf", kTets));
  EXPECT_EQ(m.type, ElementType::Tet4);
  ASSERT_EQ(m.element_count(), 2u);
  ASSERT_EQ(m.node_count(), 5u);
  EXPECT_EQ(m.connectivity, (std::vector<Index>{0, 1, 2, 3, 1, 4, 2, 3}));
  EXPECT_EQ(m.labels, (std::vector<std::int32_t>{1, 7}));
  EXPECT_DOUBLE_EQ(m.nodes(0, 1), 0.001);
  ASSERT_TRUE(m.has_fibres());
  EXPECT_DOUBLE_EQ(m.normal(1, 0), 1.0);  // z x x = y
  ASSERT_EQ(m.cell_scalars.count("scar"), 1u);
  EXPECT_DOUBLE_EQ(m.cell_scalars.at("scar")[0], 0.25);
  EXPECT_EQ(m.cell_scalars.count("u"), 0u) << "node attributes are not cell fields";
  // A tensor cell attribute (9 per cell) is not mesh data: skipped, not an error.
  const std::string tensor = R"(      <Attribute Name="stress" AttributeType="Tensor" Center="Cell">
        <DataItem DataType="Float" Dimensions="2 9" Format="XML">1 2 3 4 5 6 7 8 9 1 2 3 4 5 6 7 8 9</DataItem>
      </Attribute>
)";
  const Mesh t = read_mesh_file(
      write_file("tensor.xdmf", edit("      <Attribute Name=\"scar\"", tensor + "      <Attribute Name=\"scar\"")));
  EXPECT_EQ(t.cell_scalars.count("stress"), 0u);
  EXPECT_EQ(t.cell_scalars.size(), 1u);
}

TEST(MeshImportXdmf, ReadsTheFirstGridOfATimeSeries) {
  std::string t = kTets;
  const auto grid = t.find("    <Grid Name=\"Grid\"");
  const auto end = t.find("  </Domain>");
  const std::string one = t.substr(grid, end - grid);
  t = t.substr(0, grid) + "    <Grid Name=\"series\" GridType=\"Collection\" CollectionType=\"Temporal\">\n" + one +
      one + "    </Grid>\n" + t.substr(end);
  const Mesh m = read_mesh_file(write_file("series.xmf", t));
  EXPECT_EQ(m.element_count(), 2u);
}

TEST(MeshImportXdmf, RefusesWhatCannotBeRunNamingTheFile) {
  const auto expect_error = [](const std::string& name, const std::string& text, const std::string& what) {
    SCOPED_TRACE(name);
    const fs::path p = write_file(name + ".xdmf", text);
    try {
      (void)read_mesh_file(p);
      ADD_FAILURE() << "no error";
    } catch (const adamss::InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
  };
  expect_error("not_xml", "this is not xml", "not well-formed XML");
  expect_error("root", "<VTKFile/>", "not <Xdmf>");
  expect_error("no_grid", "<Xdmf><Domain/></Xdmf>", "no uniform <Grid>");
  expect_error("mixed", edit("TopologyType=\"Tetrahedron\"", "TopologyType=\"Mixed\""), "TopologyType 'Mixed'");
  expect_error("triangle", edit("TopologyType=\"Tetrahedron\"", "TopologyType=\"Triangle\""),
               "Tetrahedron or Hexahedron");
  expect_error("xy", edit("GeometryType=\"XYZ\"", "GeometryType=\"XY\""), "only XYZ");
  expect_error("dims", edit("Dimensions=\"2 4\"", "Dimensions=\"3 4\""), "Dimensions '3 4' but 8 values");
  expect_error("index", edit("0 1 2 3 1 4 2 3", "0 1 2 3 1 9 2 3"), "refers to node 9");
  expect_error("nan", edit("0 0 0  0.001", "nan 0 0  0.001"), "node 0 is not finite");
  expect_error("word", edit("0.25 1", "0.25 one"), "'one' is not a number");
  expect_error("label", edit(">1 7<", ">1 7.5<"), "not an integer label");
  expect_error("h5", edit("Format=\"XML\" Precision=\"8\">0 1 2 3 1 4 2 3", "Format=\"HDF\">missing.h5:/cells"),
               "missing.h5' does not exist");
  expect_error("binary", edit("Format=\"XML\" Precision=\"8\">0 1 2 3 1 4 2 3", "Format=\"Binary\">cells.bin"),
               "Format 'Binary' is not read");
  expect_error("inverted", edit("0 1 2 3 1 4 2 3", "0 2 1 3 1 4 2 3"), "element 0 is inverted");
  expect_error("frame", edit(">1 0 0 1 0 0<", ">0 0 1 1 0 0<"), "not orthonormal");
  expect_error("negative", edit("Dimensions=\"2 4\"", "Dimensions=\"-2 -4\""), "is not a valid size");
  expect_error("overflow", edit("Dimensions=\"2 4\"", "Dimensions=\"4294967296 4294967296 8\""), "is not a valid size");
  const std::string normal = R"(      <Attribute Name="normal" AttributeType="Vector" Center="Cell">
        <DataItem DataType="Float" Dimensions="2 3" Format="XML">0 -1 0 0 -1 0</DataItem>
      </Attribute>
)";
  expect_error("normal", edit("      <Attribute Name=\"scar\"", normal + "      <Attribute Name=\"scar\""),
               "normal of cell 0 is not fiber x sheet");
}
