#include "solver/run/results.hpp"

#include <lz4.h>
#include <zlib.h>

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <system_error>
#include <vector>

#include "common/durable.hpp"
#include "common/error.hpp"
#include "common/xml.hpp"
#include "preprocess/fibres/fibre_field.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "solver/geometry/element_rules.hpp"

namespace adamss::solver {

namespace fs = std::filesystem;

namespace {

using preprocess::ElementType;

/// dx/dxi (tet: edge matrix; hex, tet10 and hex27: Jacobian at the centre) of element e at positions x.
Eigen::Matrix3d element_map(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x, std::size_t e) {
  const preprocess::Index* n = mesh.element(e);
  Eigen::Matrix3d j;
  if (mesh.type == ElementType::Tet10) {
    static const Eigen::Matrix<double, 10, 3> kG = preprocess::tet10_shape_gradients(Eigen::Vector3d::Constant(0.25));
    j.setZero();
    for (Eigen::Index a = 0; a < 10; ++a) j += x.col(n[a]) * kG.row(a);
    return j;
  }
  if (mesh.type == ElementType::Tet4) {
    for (int k = 0; k < 3; ++k) j.col(k) = x.col(n[k + 1]) - x.col(n[0]);
    return j;
  }
  if (mesh.type == ElementType::Hex27) {
    static const Eigen::Matrix<double, 27, 3> kG = preprocess::hex27_shape_gradients(Eigen::Vector3d::Constant(0.5));
    j.setZero();
    for (Eigen::Index a = 0; a < 27; ++a) j += x.col(n[a]) * kG.row(a);
    return j;
  }
  static const Eigen::Matrix<double, 8, 3> kG = hex_shape_gradients(0.5, 0.5, 0.5);
  j.setZero();
  for (Eigen::Index a = 0; a < 8; ++a) j += x.col(n[a]) * kG.row(a);
  return j;
}

/// Entry e of a 9 x E tensor array (row by row) as a 3 x 3 matrix, and back.
Eigen::Matrix3d tensor_at(const Eigen::Matrix<double, 9, Eigen::Dynamic>& t, Eigen::Index e) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = t(3 * r + c, e);
  return m;
}

void set_tensor(Eigen::Matrix<double, 9, Eigen::Dynamic>& t, Eigen::Index e, const Eigen::Matrix3d& m) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) t(3 * r + c, e) = m(r, c);
}

void put_u64(std::string& buf, std::uint64_t v) {
  buf.append(reinterpret_cast<const char*>(&v), sizeof v);
}

/// One block of `n` bytes compressed as `c` says (zlib level 1 or LZ4's default), into `out`.
void compress_block(FrameCompression c, const char* src, std::size_t n, std::string& out) {
  if (c == FrameCompression::lz4) {
    out.resize(static_cast<std::size_t>(LZ4_compressBound(static_cast<int>(n))));
    const int size = LZ4_compress_default(src, out.data(), static_cast<int>(n), static_cast<int>(out.size()));
    if (size <= 0) throw IoError("LZ4 could not compress a frame array");
    out.resize(static_cast<std::size_t>(size));
    return;
  }
  uLongf size = compressBound(static_cast<uLong>(n));
  out.resize(size);
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(src), static_cast<uLong>(n),
                1) != Z_OK)
    throw IoError("zlib could not compress a frame array");
  out.resize(size);
}

/// One appended array. Compressed (zlib or LZ4) as VTK's data compressors write it (header_type
/// UInt64): the header [number of blocks, block size, size of the last partial block (0 when the
/// last block is full), compressed size of each block], then the compressed blocks, 32 KiB each
/// before compression. zlib level 1: a heart frame (498 nodes, 1248 elements, every array) is
/// 310 kB instead of ~780 kB. Uncompressed: the byte count, then the bytes.
template <class T>
void put_block(std::string& buf, const T* data, std::size_t count, FrameCompression c) {
  const std::size_t bytes = count * sizeof(T);
  const auto* src = reinterpret_cast<const char*>(data);
  if (c == FrameCompression::none) {
    put_u64(buf, bytes);
    buf.append(src, bytes);
    return;
  }
  constexpr std::size_t kBlock = 32768;
  const std::size_t blocks = (bytes + kBlock - 1) / kBlock;
  std::vector<std::string> packed(blocks);
  for (std::size_t b = 0; b < blocks; ++b)
    compress_block(c, src + b * kBlock, std::min(kBlock, bytes - b * kBlock), packed[b]);
  put_u64(buf, blocks);
  put_u64(buf, kBlock);
  put_u64(buf, bytes % kBlock);
  for (const std::string& p : packed) put_u64(buf, p.size());
  for (const std::string& p : packed) buf += p;
}

}  // namespace

void add_strain_fields(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x, VtuArrays& a) {
  const auto ne = static_cast<Eigen::Index>(mesh.element_count());
  const std::vector<Eigen::Matrix3d> F = element_deformation_gradients(mesh, x);
  Eigen::Matrix<double, 9, Eigen::Dynamic> strain(9, ne);
  for (Eigen::Index e = 0; e < ne; ++e) {
    set_tensor(strain, e,
               0.5 * (F[static_cast<std::size_t>(e)].transpose() * F[static_cast<std::size_t>(e)] -
                      Eigen::Matrix3d::Identity()));
  }
  a.cell_tensors["green_lagrange"] = strain;
  if (!mesh.has_fibres()) return;
  Eigen::Matrix<double, 9, Eigen::Dynamic> local(9, ne);
  Eigen::Matrix3Xd f(3, ne), sh(3, ne), n(3, ne);
  Eigen::VectorXd stretch(ne);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const Eigen::Matrix3d& Fe = F[static_cast<std::size_t>(e)];
    Eigen::Matrix3d Q;
    Q << mesh.fiber.col(e), mesh.sheet.col(e), mesh.normal.col(e);
    set_tensor(local, e, Q.transpose() * tensor_at(strain, e) * Q);
    f.col(e) = Fe * mesh.fiber.col(e);
    stretch[e] = f.col(e).norm();
    f.col(e) /= stretch[e];
    sh.col(e) = (Fe * mesh.sheet.col(e)).normalized();
    n.col(e) = Fe.inverse().transpose() * mesh.normal.col(e);
    n.col(e).normalize();
  }
  a.cell_tensors["green_lagrange_fibre_frame"] = local;
  a.cell_scalars["fibre_stretch"] = stretch;
  a.cell_vectors["fibre"] = mesh.fiber;
  a.cell_vectors["sheet"] = mesh.sheet;
  a.cell_vectors["normal"] = mesh.normal;
  a.cell_vectors["fibre_current"] = f;
  a.cell_vectors["sheet_current"] = sh;
  a.cell_vectors["normal_current"] = n;
}

namespace {

/// The element's fibre frame B = [f s n] (Gram-Schmidt, n = f x s, as the FEM element builds it);
/// identity without fibres or for a degenerate frame.
Eigen::Matrix3d fibre_frame_of(const preprocess::Mesh& mesh, Eigen::Index e) {
  if (!mesh.has_fibres()) return Eigen::Matrix3d::Identity();
  Eigen::Vector3d f = mesh.fiber.col(e), sh = mesh.sheet.col(e);
  if (!(f.norm() > 0.0)) return Eigen::Matrix3d::Identity();
  f.normalize();
  sh -= sh.dot(f) * f;
  if (!(sh.norm() > 0.0)) return Eigen::Matrix3d::Identity();
  sh.normalize();
  Eigen::Matrix3d b;
  b << f, sh, f.cross(sh);
  return b;
}

}  // namespace

void complete_stress_fields(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x, VtuArrays& a) {
  using Tensors = Eigen::Matrix<double, 9, Eigen::Dynamic>;
  const auto ne = static_cast<Eigen::Index>(mesh.element_count());
  const auto q = a.cell_scalars.find("volumetric_stress");
  const bool has_q = q != a.cell_scalars.end();
  if (!has_q && a.cell_tensors.count("stress_pk2") == 0) return;
  for (const char* name : {"stress_pk2", "stress_cauchy"}) {
    Tensors& t = a.cell_tensors[name];
    if (t.cols() != ne) t = Tensors::Zero(9, ne);
  }
  Tensors& pk2 = a.cell_tensors["stress_pk2"];
  Tensors& cauchy = a.cell_tensors["stress_cauchy"];
  Tensors pk2f(9, ne);
  Eigen::VectorXd pressure(ne);
  const std::vector<Eigen::Matrix3d> F =
      has_q ? element_deformation_gradients(mesh, x) : std::vector<Eigen::Matrix3d>{};
  for (Eigen::Index e = 0; e < ne; ++e) {
    Eigen::Matrix3d S = tensor_at(pk2, e), sigma = tensor_at(cauchy, e);
    if (has_q) {
      // sigma_vol = q I; S_vol = J F^-1 sigma_vol F^-T = q J C^-1.
      const Eigen::Matrix3d& Fe = F[static_cast<std::size_t>(e)];
      const double J = Fe.determinant(), qe = q->second[e];
      sigma += qe * Eigen::Matrix3d::Identity();
      S += qe * J * (Fe.transpose() * Fe).inverse();
      set_tensor(pk2, e, S);
      set_tensor(cauchy, e, sigma);
    }
    const Eigen::Matrix3d B = fibre_frame_of(mesh, e);
    set_tensor(pk2f, e, B.transpose() * S * B);
    pressure[e] = -sigma.trace() / 3.0;
  }
  a.cell_tensors["stress_pk2_fibre_frame"] = pk2f;
  a.cell_scalars["pressure"] = pressure;
}

void add_cardiac_strain_fields(const preprocess::Mesh& mesh, const LongAxis& axis, VtuArrays& a) {
  const auto it = a.cell_tensors.find("green_lagrange");
  if (it == a.cell_tensors.end()) return;
  const Eigen::Matrix<double, 9, Eigen::Dynamic>& strain = it->second;
  const Eigen::Index ne = strain.cols();
  Eigen::Matrix<double, 9, Eigen::Dynamic> local(9, ne);
  Eigen::Matrix3Xd ec(3, ne), el(3, ne), er(3, ne);
  Eigen::VectorXd cc(ne), ll(ne), rr(ne);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const Eigen::Matrix3d Q = cardiac_frame(axis, preprocess::element_barycentre(mesh, static_cast<std::size_t>(e)));
    const Eigen::Matrix3d El = Q.transpose() * tensor_at(strain, e) * Q;
    set_tensor(local, e, El);
    ec.col(e) = Q.col(0);
    el.col(e) = Q.col(1);
    er.col(e) = Q.col(2);
    cc[e] = El(0, 0);
    ll[e] = El(1, 1);
    rr[e] = El(2, 2);
  }
  a.cell_tensors["green_lagrange_cardiac"] = local;
  a.cell_vectors["circumferential"] = ec;
  a.cell_vectors["longitudinal"] = el;
  a.cell_vectors["radial"] = er;
  a.cell_scalars["strain_circumferential"] = cc;
  a.cell_scalars["strain_longitudinal"] = ll;
  a.cell_scalars["strain_radial"] = rr;
}

std::vector<double> element_volumes(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x) {
  std::vector<double> v(mesh.element_count());
  for (std::size_t e = 0; e < v.size(); ++e) v[e] = element_volume_at(mesh, x, e);
  return v;
}

Eigen::VectorXd element_volume_ratio(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x,
                                     const std::vector<double>& volume0) {
  const std::vector<double> v = element_volumes(mesh, x);
  Eigen::VectorXd j(static_cast<Eigen::Index>(v.size()));
  for (std::size_t e = 0; e < v.size(); ++e) j[static_cast<Eigen::Index>(e)] = v[e] / volume0[e];
  return j;
}

std::vector<Eigen::Matrix3d> element_deformation_gradients(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x) {
  std::vector<Eigen::Matrix3d> out(mesh.element_count());
  for (std::size_t e = 0; e < out.size(); ++e) {
    out[e] = element_map(mesh, x, e) * element_map(mesh, mesh.nodes, e).inverse();
  }
  return out;
}

Eigen::VectorXd fibre_stretch(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x) {
  const std::size_t ne = mesh.element_count();
  Eigen::VectorXd out = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(ne));
  if (!mesh.has_fibres()) return out;
  const std::vector<Eigen::Matrix3d> F = element_deformation_gradients(mesh, x);
  for (std::size_t e = 0; e < ne; ++e) {
    out[static_cast<Eigen::Index>(e)] = (F[e] * mesh.fiber.col(static_cast<Eigen::Index>(e))).norm();
  }
  return out;
}

namespace {

/// A field-data string as VTK's XML reader expects an ascii vtkStringArray: the byte values,
/// space separated, and a 0 ending the string.
std::string vtk_ascii_string(const std::string& s) {
  std::string out;
  for (const char c : s) out += std::to_string(static_cast<unsigned char>(c)) + " ";
  return out + "0";
}

}  // namespace

void write_vtu(const fs::path& path, const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& points,
               const VtuArrays& arrays, FrameCompression compression) {
  const std::size_t nn = mesh.node_count(), ne = mesh.element_count();
  const int k = preprocess::nodes_per_element(mesh.type);
  std::ostringstream head;
  std::string data;
  // Each array's offset is where its block starts in the appended data (put_block follows).
  auto declare = [&](const std::string& type, const std::string& name, int comps, std::size_t /*bytes*/) {
    head << "        <DataArray type=\"" << type << "\" Name=\"" << xml_escape(name) << "\" NumberOfComponents=\""
         << comps << "\" format=\"appended\" offset=\"" << data.size() << "\"/>\n";
  };
  const char* compressor = compression == FrameCompression::zlib  ? " compressor=\"vtkZLibDataCompressor\""
                           : compression == FrameCompression::lz4 ? " compressor=\"vtkLZ4DataCompressor\""
                                                                  : "";
  head << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
          "header_type=\"UInt64\""
       << compressor << ">\n  <UnstructuredGrid>\n";
  if (!arrays.field_scalars.empty() || !arrays.field_strings.empty()) {
    head << "    <FieldData>\n" << std::setprecision(17);
    for (const auto& [name, v] : arrays.field_scalars) {
      head << "      <DataArray type=\"Float64\" Name=\"" << xml_escape(name)
           << "\" NumberOfTuples=\"1\" format=\"ascii\">" << v << "</DataArray>\n";
    }
    for (const auto& [name, v] : arrays.field_strings) {
      head << "      <DataArray type=\"String\" Name=\"" << xml_escape(name)
           << "\" NumberOfTuples=\"1\" format=\"ascii\">" << vtk_ascii_string(v) << "</DataArray>\n";
    }
    head << "    </FieldData>\n";
  }
  head << "    <Piece NumberOfPoints=\"" << nn << "\" NumberOfCells=\"" << ne << "\">\n      <Points>\n";
  declare("Float64", "Points", 3, 3 * nn * 8);
  put_block(data, points.data(), 3 * nn, compression);
  head << "      </Points>\n      <Cells>\n";
  {
    std::vector<std::int64_t> conn(mesh.connectivity.begin(), mesh.connectivity.end());
    std::vector<std::int64_t> offs(ne);
    for (std::size_t e = 0; e < ne; ++e) offs[e] = static_cast<std::int64_t>((e + 1) * static_cast<std::size_t>(k));
    // VTK_TETRA 10, VTK_HEXAHEDRON 12, VTK_QUADRATIC_TETRA 24 (corners, then mid-edge nodes).
    const std::uint8_t vtk_type = mesh.type == ElementType::Tet4    ? 10
                                  : mesh.type == ElementType::Tet10 ? 24
                                  : mesh.type == ElementType::Hex27 ? 29
                                                                    : 12;
    std::vector<std::uint8_t> types(ne, vtk_type);
    declare("Int64", "connectivity", 1, conn.size() * 8);
    put_block(data, conn.data(), conn.size(), compression);
    declare("Int64", "offsets", 1, ne * 8);
    put_block(data, offs.data(), ne, compression);
    declare("UInt8", "types", 1, ne);
    put_block(data, types.data(), ne, compression);
  }
  // The displacement is the active vector (ParaView's Warp By Vector picks it).
  head << "      </Cells>\n      <PointData"
       << (arrays.point_vectors.count("displacement") ? " Vectors=\"displacement\"" : "") << ">\n";
  for (const auto& [name, m] : arrays.point_vectors) {
    declare("Float64", name, 3, 3 * nn * 8);
    put_block(data, m.data(), 3 * nn, compression);
  }
  head << "      </PointData>\n      <CellData>\n";
  declare("Int32", "label", 1, ne * 4);
  put_block(data, mesh.labels.data(), ne, compression);
  for (const auto& [name, v] : arrays.cell_scalars) {
    declare("Float64", name, 1, ne * 8);
    put_block(data, v.data(), ne, compression);
  }
  for (const auto& [name, m] : arrays.cell_vectors) {
    declare("Float64", name, 3, 3 * ne * 8);
    put_block(data, m.data(), 3 * ne, compression);
  }
  for (const auto& [name, m] : arrays.cell_tensors) {
    declare("Float64", name, 9, 9 * ne * 8);
    put_block(data, m.data(), 9 * ne, compression);
  }
  head << "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";

  replace_file(path, {head.str(), data, "\n  </AppendedData>\n</VTKFile>\n"});
}

ResultsWriter::ResultsWriter(fs::path out_dir, const Model& model, const StateArchive* resume)
    : dir_(std::move(out_dir)), model_(model), resuming_(resume != nullptr), log_(dir_ / "run.log") {
  element_volume0_ = element_volumes(*model.mesh, model.x_ref);
  for (const double v : element_volume0_) volume0_ += v;
  if (resume != nullptr) resume_from(*resume);
}

void ResultsWriter::open() {
  if (opened_) return;
  opened_ = true;
  if (muted_) {
    started_ = true;
    return;
  }
  if (resuming_) {
    started_ = true;
    continue_series();
    log_.open(true);
    return;
  }
  archive_previous();
  started_ = true;
  log_.open(false);
  std::error_code ec;
  fs::create_directories(dir_ / "frames", ec);
  if (ec) throw IoError("cannot create the output folder " + (dir_ / "frames").string() + ": " + ec.message());
  globals_.open(dir_ / "globals.csv");
  globals_ << globals_header();
  globals_.flush();
  if (!globals_) throw IoError("cannot write " + (dir_ / "globals.csv").string());
  globals_ << std::setprecision(10);
}

void ResultsWriter::archive_previous() {
  static const char* const kRunFiles[] = {"summary.json", "globals.csv",   "series.pvd",
                                          "frames",       "checkpoint.h5", "run.log"};
  std::vector<std::string> present;
  for (const char* name : kRunFiles) {
    std::error_code ec;
    if (fs::exists(dir_ / name, ec)) present.emplace_back(name);
  }
  if (present.empty()) return;
  const fs::path previous = dir_ / "previous";
  std::error_code ec;
  fs::remove_all(previous, ec);
  if (!ec) fs::create_directory(previous, ec);
  if (ec) throw IoError("cannot make " + previous.string() + " for the earlier run's results: " + ec.message());
  for (const std::string& name : present) {
    fs::rename(dir_ / name, previous / name, ec);
    if (ec) {
      throw IoError("cannot move the earlier run's " + (dir_ / name).string() + " to " + previous.string() + ": " +
                    ec.message());
    }
  }
}

std::string ResultsWriter::globals_header() const {
  std::ostringstream h;
  h << "step,t,dt,kinetic_energy,total_volume,volume_change,element_volume_change_max,barycentre_x,barycentre_y,"
       "barycentre_z";
  for (const auto& c : model_.cavities) {
    h << ',' << c->name() << "_volume," << c->name() << "_pressure";
    for (const std::string& col : c->column_names()) h << ',' << c->name() << '_' << col;
  }
  h << ",force_evaluations,rejected_steps,abm3_error,newton_iterations,linear_iterations,wall_time\n";
  return h.str();
}

void ResultsWriter::save_state(StateArchive& archive) const {
  std::vector<double> times;
  for (const auto& fr : frames_) times.push_back(fr.first);
  archive.put("frame_times", times);
  archive.put_int("globals_rows", static_cast<std::int64_t>(rows_));
  archive.put_int("logged", logged_ ? 1 : 0);
  archive.put("volume_change_max", max_volume_change_);
  archive.put("fibre_stretch", std::vector<double>{stretch_min_, stretch_max_});
  std::vector<double> ex;
  for (const Extremum& e : extrema_)
    ex.insert(ex.end(), {e.min, e.max, e.t_min, e.t_max, e.p_at_min, e.p_at_max, e.p_max});
  archive.put("cavity_extrema", ex);
}

void ResultsWriter::resume_from(const StateArchive& archive) {
  // Everything is checked before anything in the folder changes.
  const std::string& src = archive.source();
  frames_.clear();
  for (const double t : archive.doubles("frame_times")) {
    char name[64];
    std::snprintf(name, sizeof name, "frame_%05zu.vtu", frames_.size());
    if (!fs::exists(dir_ / "frames" / name)) {
      throw InputError("cannot resume from " + src + ": " + (dir_ / "frames" / name).string() +
                       " is missing (resume into the folder the checkpoint was written in)");
    }
    frames_.emplace_back(t, std::string("frames/") + name);
  }
  rows_ = static_cast<std::size_t>(archive.integer("globals_rows"));
  logged_ = archive.integer("logged") != 0;
  max_volume_change_ = archive.scalar("volume_change_max");
  const auto& st = archive.doubles("fibre_stretch");
  if (st.size() != 2) throw InputError(src + ": writer/fibre_stretch should hold 2 values");
  stretch_min_ = st[0];
  stretch_max_ = st[1];
  const auto& ex = archive.doubles("cavity_extrema");
  if (ex.size() % 7 != 0 || (ex.size() != 0 && ex.size() / 7 != model_.cavities.size())) {
    throw InputError(src + ": writer/cavity_extrema does not match the scene's " +
                     std::to_string(model_.cavities.size()) + " cavities");
  }
  extrema_.clear();
  for (std::size_t k = 0; k + 7 <= ex.size(); k += 7)
    extrema_.push_back({ex[k], ex[k + 1], ex[k + 2], ex[k + 3], ex[k + 4], ex[k + 5], ex[k + 6]});
  // globals.csv: the header and the first rows_ rows (later rows of the interrupted run, and a
  // partial last line of a killed one, are dropped).
  const fs::path csv = dir_ / "globals.csv";
  std::string kept;
  {
    std::ifstream in(csv);
    if (!in) throw InputError("cannot resume from " + src + ": " + csv.string() + " is missing");
    std::string line;
    std::getline(in, line);
    if (line + "\n" != globals_header()) {
      throw InputError("cannot resume from " + src + ": the header of " + csv.string() +
                       " does not match the scene (a different scene wrote that folder)");
    }
    kept = line + "\n";
    std::size_t n = 0;
    while (n < rows_ && std::getline(in, line)) {
      if (in.eof()) break;  // a last line without its newline is an incomplete row
      kept += line + "\n";
      ++n;
    }
    if (n != rows_) {
      throw InputError("cannot resume from " + src + ": " + csv.string() + " has " + std::to_string(n) +
                       " complete rows, the checkpoint counted " + std::to_string(rows_));
    }
  }
  resume_globals_ = std::move(kept);
}

void ResultsWriter::continue_series() {
  const fs::path csv = dir_ / "globals.csv";
  replace_file(csv, {resume_globals_});
  resume_globals_.clear();
  globals_.open(csv, std::ios::app);
  if (!globals_) throw IoError("cannot append to " + csv.string());
  globals_ << std::setprecision(10);
  // Frames the interrupted run wrote after the checkpoint (its final frame) are not part of the series.
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir_ / "frames")) {
    const std::string stem = entry.path().stem().string();
    if (entry.path().extension() != ".vtu" || stem.rfind("frame_", 0) != 0) continue;
    if (std::strtoull(stem.c_str() + 6, nullptr, 10) >= frames_.size()) fs::remove(entry.path(), ec);
  }
  if (!frames_.empty()) write_pvd();
}

void ResultsWriter::write_frame(const State& s, const Eigen::Matrix3Xd& f) {
  if (muted_) {
    frames_.emplace_back(s.t, std::string());
    return;
  }
  const preprocess::Mesh& mesh = *model_.mesh;
  VtuArrays a;
  a.point_vectors["displacement"] = s.x - model_.x_ref;
  a.point_vectors["velocity"] = s.v;
  a.point_vectors["force"] = f;
  a.cell_scalars["J"] = element_volume_ratio(mesh, s.x, element_volume0_);
  add_strain_fields(mesh, s.x, a);
  // The mesh's own cell fields (a scar segment, the transmural coordinate, ...), so a frame shows
  // where the scar is; a term's field of the same name takes precedence.
  for (const auto& [name, v] : mesh.cell_scalars) a.cell_scalars.emplace(name, v);
  const StateView view{s.x, s.v, s.t};
  for (const auto& term : model_.terms) {
    term->add_cell_fields(view, mesh.element_count(), a.cell_scalars);
    term->add_cell_tensors(view, mesh.element_count(), a.cell_tensors);
  }
  complete_stress_fields(mesh, s.x, a);
  if (model_.long_axis) add_cardiac_strain_fields(mesh, *model_.long_axis, a);
  a.field_scalars["TimeValue"] = s.t;
  for (const auto& c : model_.cavities) {
    const double p = c->pressure(s.t), v = c->volume(s.x);
    a.field_scalars[c->name() + "_pressure_Pa"] = p;
    a.field_scalars[c->name() + "_pressure_mmHg"] = p / 133.322387415;
    a.field_scalars[c->name() + "_volume_ml"] = v * 1e6;
    if (const std::string phase = c->phase(); !phase.empty()) a.field_strings[c->name() + "_phase"] = phase;
  }
  char name[64];
  std::snprintf(name, sizeof name, "frame_%05zu.vtu", frames_.size());
  // Reference points + displacement: Warp By Vector (scale 1) gives the deformed mesh once.
  write_vtu(dir_ / "frames" / name, mesh, model_.x_ref, a, compression_);
  frames_.emplace_back(s.t, std::string("frames/") + name);
  write_pvd();
}

void ResultsWriter::write_pvd() const {
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n"
      << std::setprecision(12);
  for (const auto& [t, file] : frames_)
    out << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
  replace_file(dir_ / "series.pvd", {out.str()});
}

void ResultsWriter::write_globals(const State& s, const GlobalsRow& row) {
  if (muted_) {
    ++rows_;
    return;
  }
  // Total volume (as total_volume()) and the largest element change max_e |V_e / V0_e - 1| in one pass.
  double vol = 0.0, element_change = 0.0;
  for (std::size_t e = 0; e < element_volume0_.size(); ++e) {
    const double ve = element_volume_at(*model_.mesh, s.x, e);
    vol += ve;
    element_change = std::max(element_change, std::abs(ve / element_volume0_[e] - 1.0));
  }
  const Eigen::Vector3d bary =
      (s.x.array().rowwise() * model_.mass.transpose().array()).rowwise().sum().matrix() / model_.mass.sum();
  globals_ << row.step << ',' << s.t << ',' << row.dt << ',' << row.kinetic_energy << ',' << vol << ','
           << (vol - volume0_) / volume0_ << ',' << element_change << ',' << bary.x() << ',' << bary.y() << ','
           << bary.z();
  if (extrema_.size() != model_.cavities.size()) extrema_.assign(model_.cavities.size(), {});
  const bool first = !logged_;
  logged_ = true;
  max_volume_change_ = std::max(max_volume_change_, std::abs(vol - volume0_) / volume0_);
  if (model_.mesh->has_fibres()) {
    const Eigen::VectorXd st = fibre_stretch(*model_.mesh, s.x);
    if (st.size() > 0) {
      stretch_min_ = first ? st.minCoeff() : std::min(stretch_min_, st.minCoeff());
      stretch_max_ = first ? st.maxCoeff() : std::max(stretch_max_, st.maxCoeff());
    }
  }
  for (std::size_t k = 0; k < model_.cavities.size(); ++k) {
    const auto& c = model_.cavities[k];
    const double cv = c->volume(s.x);
    const double cp = c->pressure(s.t);
    Extremum& e = extrema_[k];
    if (first || cv < e.min) {
      e.min = cv;
      e.t_min = s.t;
      e.p_at_min = cp;
    }
    if (first || cv > e.max) {
      e.max = cv;
      e.t_max = s.t;
      e.p_at_max = cp;
    }
    e.p_max = first ? cp : std::max(e.p_max, cp);
    globals_ << ',' << cv << ',' << cp;
    for (const double v : c->column_values()) globals_ << ',' << v;
  }
  globals_ << ',' << row.report.evaluations << ',' << row.report.rejected << ',' << row.report.error << ','
           << row.report.newton_iterations << ',' << row.report.linear_iterations << ',' << row.wall_seconds << '\n';
  globals_.flush();
  if (!globals_) throw IoError("cannot append a row to " + (dir_ / "globals.csv").string() + " (disk full?)");
  ++rows_;
}

void ResultsWriter::write_checkpoint(const State& s, std::size_t step) const {
  StateArchive a;
  a.put("x", s.x);
  a.put("v", s.v);
  a.put_int("run/resumable", 0);
  write_checkpoint(a, s.t, step);
}

void ResultsWriter::write_checkpoint(const StateArchive& archive, double t, std::size_t step) const {
  if (muted_) return;
  archive.write_hdf5(dir_ / "checkpoint.h5", {{"t", t}, {"step", static_cast<double>(step)}});
}

}  // namespace adamss::solver
