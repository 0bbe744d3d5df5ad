// XDMF (2 and 3) meshes read into a Mesh: see mesh_import.hpp. The light data is XML (parsed by
// VTK's vtkXMLDataParser); the heavy data is in HDF5 files ("file.h5:/path", relative to the .xdmf)
// or inline in the XML. Written by meshio, dolfinx/FEniCS (XDMFFile), adamss (mesh.xdmf) and
// ParaView; the first uniform grid is read (of a time series: its first step).
#include <hdf5.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/mesh/hdf5_handle.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "preprocess/mesh/vtk/vtk_errors.hpp"
#include "preprocess/mesh/vtk/vtk_module.hpp"

namespace adamss::preprocess::vtk_io {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string attr(vtkXMLDataElement* e, const char* name, const std::string& fallback = "") {
  const char* v = e->GetAttribute(name);
  return v != nullptr ? std::string(v) : fallback;
}

/// The first child element named `name` (case-sensitive, as XDMF), or nullptr.
vtkXMLDataElement* child(vtkXMLDataElement* e, const char* name) {
  for (int i = 0; i < e->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* c = e->GetNestedElement(i);
    if (std::strcmp(c->GetName(), name) == 0) return c;
  }
  return nullptr;
}

/// The first uniform grid under `e` (depth first through collections and trees), or nullptr.
vtkXMLDataElement* first_uniform_grid(vtkXMLDataElement* e) {
  for (int i = 0; i < e->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* c = e->GetNestedElement(i);
    if (std::strcmp(c->GetName(), "Grid") != 0) continue;
    const std::string type = lower(attr(c, "GridType", "Uniform"));
    if (type == "uniform") return c;
    if (vtkXMLDataElement* g = first_uniform_grid(c)) return g;
  }
  return nullptr;
}

/// A DataItem's values as doubles and its dimensions (from its Dimensions attribute).
struct Values {
  std::vector<double> data;
  std::vector<long long> dims;
};

Values read_hdf(const std::filesystem::path& h5, const std::string& dataset, const std::string& where) {
  const SilenceHdf5Errors quiet;
  if (!std::filesystem::exists(h5)) throw InputError(where + ": its HDF5 file '" + h5.string() + "' does not exist");
  const Hdf5Handle file(H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw InputError(where + ": cannot open '" + h5.string() + "' as HDF5");
  const Hdf5Handle set(H5Dopen2(file.get(), dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (!set.valid()) throw InputError(where + ": '" + h5.string() + "' has no dataset '" + dataset + "'");
  const Hdf5Handle space(H5Dget_space(set.get()), H5Sclose);
  const hssize_t n = space.valid() ? H5Sget_simple_extent_npoints(space.get()) : -1;
  hsize_t file_size = 0;
  if (n < 0 || H5Fget_filesize(file.get(), &file_size) < 0)
    throw InputError(where + ": cannot query '" + dataset + "'");
  // A corrupt file may claim any size; deflate compresses at most ~1000:1 (see mesh_io_h5.cpp).
  if (static_cast<double>(n) * 8.0 > 1100.0 * static_cast<double>(file_size) + 1048576.0)
    throw InputError(where + ": dataset '" + dataset + "' claims more values than its file can hold (corrupted?)");
  Values v;
  v.data.resize(static_cast<std::size_t>(n));
  if (n > 0 && H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data.data()) < 0)
    throw InputError(where + ": cannot read dataset '" + dataset + "' of '" + h5.string() + "' as numbers");
  return v;
}

Values read_item(vtkXMLDataElement* item, const std::filesystem::path& dir, const std::string& where) {
  if (item == nullptr) throw InputError(where + ": no DataItem");
  const std::string what = where + " DataItem";
  if (!attr(item, "Reference").empty() || lower(attr(item, "ItemType", "Uniform")) != "uniform")
    throw InputError(what + ": only plain (uniform, not referenced or computed) data items are read");
  const std::string format = lower(attr(item, "Format", "XML"));
  std::string text = item->GetCharacterData() != nullptr ? item->GetCharacterData() : "";
  Values v;
  if (format == "hdf") {
    text.erase(0, text.find_first_not_of(" \t\r\n"));
    text.erase(text.find_last_not_of(" \t\r\n") + 1);
    const auto colon = text.find(":/");  // (a dataset path may hold ':' itself)
    if (colon == std::string::npos || colon == 0)
      throw InputError(what + ": expected FILE.h5:/DATASET, found '" + text.substr(0, 80) + "'");
    std::filesystem::path h5 = text.substr(0, colon);
    if (h5.is_relative()) h5 = dir / h5;
    v = read_hdf(h5, text.substr(colon + 1), what);
  } else if (format == "xml") {
    std::istringstream in(text);
    std::string token;
    while (in >> token) {
      char* end = nullptr;
      const double x = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0')
        throw InputError(what + ": '" + token.substr(0, 40) + "' is not a number");
      v.data.push_back(x);
    }
  } else {
    throw InputError(what + ": Format '" + attr(item, "Format") + "' is not read (HDF or XML only)");
  }
  std::istringstream dims(attr(item, "Dimensions"));
  long long d = 0;
  long long product = 1;
  while (dims >> d) {
    if (d < 0 || __builtin_mul_overflow(product, d, &product))
      throw InputError(what + ": Dimensions '" + attr(item, "Dimensions") + "' is not a valid size");
    v.dims.push_back(d);
  }
  if (!v.dims.empty() && product != static_cast<long long>(v.data.size())) {
    throw InputError(what + ": Dimensions '" + attr(item, "Dimensions") + "' but " + std::to_string(v.data.size()) +
                     " values");
  }
  return v;
}

}  // namespace

Mesh read_mesh_xdmf(const std::filesystem::path& path) {
  const std::string where = existing_mesh_file(path);
  vtkNew<vtkXMLDataParser> parser;
  auto errors = vtkSmartPointer<ErrorCatcher>::New();  // (VTK would print the parse error itself)
  parser->AddObserver(vtkCommand::ErrorEvent, errors);
  parser->SetFileName(path.c_str());
  parser->SetIgnoreCharacterData(0);
  if (parser->Parse() == 0 || parser->GetRootElement() == nullptr) {
    throw InputError("cannot read mesh " + where + ": not well-formed XML" +
                     (errors->message.empty() ? std::string() : " (" + errors->message + ")"));
  }
  vtkXMLDataElement* root = parser->GetRootElement();
  if (std::strcmp(root->GetName(), "Xdmf") != 0)
    throw InputError(where + ": the root element is <" + std::string(root->GetName()) + ">, not <Xdmf>");
  vtkXMLDataElement* domain = child(root, "Domain");
  vtkXMLDataElement* grid = domain != nullptr ? first_uniform_grid(domain) : nullptr;
  if (grid == nullptr) throw InputError(where + ": no uniform <Grid> in its <Domain>");
  const std::filesystem::path dir = path.parent_path();
  vtkXMLDataElement* topo = child(grid, "Topology");
  vtkXMLDataElement* geom = child(grid, "Geometry");
  if (topo == nullptr || geom == nullptr) throw InputError(where + ": the grid has no <Topology> or no <Geometry>");
  const std::string ttype = lower(attr(topo, "TopologyType", attr(topo, "Type")));
  Mesh mesh;
  if (ttype == "tetrahedron") {
    mesh.type = ElementType::Tet4;
  } else if (ttype == "hexahedron") {
    mesh.type = ElementType::Hex8;
  } else {
    throw InputError(where + ": TopologyType '" + attr(topo, "TopologyType", attr(topo, "Type")) +
                     "'; adamss runs Tetrahedron or Hexahedron grids (one cell type, linear)");
  }
  const std::string gtype = lower(attr(geom, "GeometryType", attr(geom, "Type", "XYZ")));
  if (gtype != "xyz") throw InputError(where + ": GeometryType '" + gtype + "'; only XYZ is read");
  const Values x = read_item(child(geom, "DataItem"), dir, where + " <Geometry>");
  if (x.data.empty() || x.data.size() % 3 != 0) throw InputError(where + ": the geometry is not n x 3 coordinates");
  const auto nn = static_cast<Eigen::Index>(x.data.size() / 3);
  mesh.nodes.resize(3, nn);
  for (Eigen::Index i = 0; i < nn; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double v = x.data[static_cast<std::size_t>(3 * i + c)];
      if (!std::isfinite(v)) throw InputError(where + ": node " + std::to_string(i) + " is not finite");
      mesh.nodes(c, i) = v;
    }
  }
  const int k = nodes_per_element(mesh.type);
  const Values t = read_item(child(topo, "DataItem"), dir, where + " <Topology>");
  if (t.data.empty() || t.data.size() % static_cast<std::size_t>(k) != 0)
    throw InputError(where + ": the topology is not a list of " + std::to_string(k) + "-node cells");
  mesh.connectivity.reserve(t.data.size());
  for (const double v : t.data) {
    if (v != std::round(v) || v < 0 || v >= static_cast<double>(nn)) {
      std::ostringstream os;
      os << where << ": a cell refers to node " << v << " (nodes 0.." << nn - 1 << ")";
      throw InputError(os.str());
    }
    mesh.connectivity.push_back(static_cast<Index>(v));
  }
  const std::size_t ne = mesh.element_count();
  mesh.labels.assign(ne, 1);
  Eigen::Matrix3Xd fibre, sheet, normal;
  for (int i = 0; i < grid->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* a = grid->GetNestedElement(i);
    if (std::strcmp(a->GetName(), "Attribute") != 0 || lower(attr(a, "Center", "Node")) != "cell") continue;
    const std::string name = attr(a, "Name");
    const Values v = read_item(child(a, "DataItem"), dir, where + " attribute '" + name + "'");
    const std::size_t comps = v.data.size() / std::max<std::size_t>(ne, 1);
    if (comps * ne != v.data.size() || comps == 0) {
      throw InputError(where + ": attribute '" + name + "' has " + std::to_string(v.data.size()) + " values for " +
                       std::to_string(ne) + " cells");
    }
    if (comps != 1 && comps != 3) continue;  // tensors and the like: not mesh data
    if (comps == 3) {
      Eigen::Matrix3Xd m = Eigen::Map<const Eigen::Matrix3Xd>(v.data.data(), 3, static_cast<Eigen::Index>(ne));
      if (name == "fiber" || name == "fibre") fibre = m;
      if (name == "sheet") sheet = m;
      if (name == "normal") normal = m;
      continue;
    }
    if (name == "label" || name == "gmsh:physical" || name == "medit:ref") {
      if (name != "label" && mesh.attributes.count("label_source") != 0) continue;  // "label" wins
      for (std::size_t e = 0; e < ne; ++e) {
        const double l = v.data[e];
        if (l != std::round(l) || std::abs(l) > 2e9) {
          throw InputError(where + ": attribute '" + name + "' of cell " + std::to_string(e) +
                           " is not an integer label");
        }
        mesh.labels[e] = static_cast<std::int32_t>(l);
      }
      mesh.attributes["label_source"] = name;
      continue;
    }
    mesh.cell_scalars[name] = Eigen::Map<const Eigen::VectorXd>(v.data.data(), static_cast<Eigen::Index>(ne));
  }
  if (fibre.cols() > 0) {
    const bool given_normal = normal.cols() > 0;
    set_imported_fibres(mesh, fibre, sheet, normal, where, "a fiber attribute needs a sheet attribute (3 per cell)");
    for (Eigen::Index e = 0; given_normal && e < fibre.cols(); ++e) {
      if ((mesh.normal.col(e) - fibre.col(e).cross(sheet.col(e))).norm() > 1e-3)
        throw InputError(where + ": the normal of cell " + std::to_string(e) + " is not fiber x sheet");
    }
  }
  check_element_orientation(mesh, where, "VTK/XDMF node order expected");
  mesh.attributes["source"] = path.string();
  return mesh;
}

}  // namespace adamss::preprocess::vtk_io
