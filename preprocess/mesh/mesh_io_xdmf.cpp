#include "preprocess/mesh/mesh_io_xdmf.hpp"

#include <sstream>
#include <string>

#include "common/durable.hpp"
#include "common/error.hpp"
#include "common/xml.hpp"

namespace adamss::preprocess {

namespace {

/// A DataItem pointing at dataset `path` of the HDF5 file `h5` (a name relative to the .xdmf).
std::string item(const std::string& h5, const std::string& path, std::size_t rows, int cols, const char* type,
                 int precision) {
  std::ostringstream o;
  o << "        <DataItem Dimensions=\"" << rows;
  if (cols > 1) o << " " << cols;
  o << "\" NumberType=\"" << type << "\" Precision=\"" << precision << "\" Format=\"HDF\">" << h5 << ":" << path
    << "</DataItem>\n";
  return o.str();
}

}  // namespace

void write_mesh_xdmf(const std::filesystem::path& xdmf, const std::filesystem::path& h5, const Mesh& mesh) {
  const std::size_t n = mesh.node_count(), e = mesh.element_count();
  const int k = nodes_per_element(mesh.type);
  const std::string file = xml_escape(h5.filename().string());
  std::ostringstream o;
  o << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
    << "    <Grid Name=\"" << xml_escape(h5.stem().string()) << "\" GridType=\"Uniform\">\n"
    << "      <Topology TopologyType=\""
    << (mesh.type == ElementType::Tet4    ? "Tetrahedron"
        : mesh.type == ElementType::Tet10 ? "Tetrahedron_10"
        : mesh.type == ElementType::Hex27 ? "Hexahedron_27"
                                          : "Hexahedron")
    << "\" NumberOfElements=\"" << e << "\" NodesPerElement=\"" << k << "\">\n"
    << item(file, "/elements/connectivity", e, k, "Int", 4) << "      </Topology>\n"
    << "      <Geometry GeometryType=\"XYZ\">\n"
    << item(file, "/nodes", n, 3, "Float", 8) << "      </Geometry>\n"
    << "      <Attribute Name=\"label\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
    << item(file, "/elements/label", e, 1, "Int", 4) << "      </Attribute>\n";
  if (mesh.has_fibres()) {
    for (const char* v : {"fiber", "sheet", "normal"}) {
      o << "      <Attribute Name=\"" << v << "\" AttributeType=\"Vector\" Center=\"Cell\">\n"
        << item(file, std::string("/elements/") + v, e, 3, "Float", 8) << "      </Attribute>\n";
    }
  }
  for (const auto& [name, values] : mesh.cell_scalars) {
    o << "      <Attribute Name=\"" << xml_escape(name) << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
      << item(file, "/elements/scalars/" + xml_escape(name), e, 1, "Float", 8) << "      </Attribute>\n";
  }
  o << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  replace_file(xdmf, {o.str()});
}

}  // namespace adamss::preprocess
