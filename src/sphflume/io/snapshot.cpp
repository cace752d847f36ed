#include "sphflume/io/snapshot.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <hdf5.h>

#include "sphflume/io/h5util.hpp"
#include "sphflume/io/restart.hpp"

namespace sph {
namespace fs = std::filesystem;

void write_file_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError(fmt::format("cannot write '{}': {}", tmp, std::strerror(errno)));
    out << text;
    out.flush();
    if (!out) {
      const std::string why = std::strerror(errno);
      out.close();
      std::error_code ec;
      fs::remove(tmp, ec);
      throw IoError(fmt::format("writing '{}' failed (disk full?): {}", path, why));
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw IoError(fmt::format("cannot rename '{}' to '{}': {}", tmp, path, ec.message()));
}

namespace {

/// The datasets and attributes of a particle file, into the open file fid (rows: this rank's
/// block of a file every rank writes together; null for one process).
template <int D>
void write_contents(hid_t fid, const std::string& tmp, const ParticleStore<D>& P, double t, long step, const RunState* rs,
                    const h5::Rows* rows) {
  const std::size_t n = P.n_owned();
  std::vector<double> buf(n * 3, 0.0);
  auto vec3 = [&](const std::vector<Vec<D>>& v) {
    for (std::size_t i = 0; i < n; ++i) {
      buf[3 * i] = v[i][0];
      buf[3 * i + 1] = D == 3 ? v[i][1] : 0.0;
      buf[3 * i + 2] = v[i][D - 1];
    }
    return buf.data();
  };
  h5::write_dataset(fid, "position", H5T_NATIVE_DOUBLE, vec3(P.pos), n, 3, tmp, rows);
  h5::write_dataset(fid, "velocity", H5T_NATIVE_DOUBLE, vec3(P.vel), n, 3, tmp, rows);
  h5::write_dataset(fid, "pressure", H5T_NATIVE_DOUBLE, P.p.data(), n, 1, tmp, rows);
  h5::write_dataset(fid, "density", H5T_NATIVE_DOUBLE, P.rho.data(), n, 1, tmp, rows);
  h5::write_dataset(fid, "mass", H5T_NATIVE_DOUBLE, P.mass.data(), n, 1, tmp, rows);
  std::vector<std::int32_t> kind(n);
  for (std::size_t i = 0; i < n; ++i) kind[i] = static_cast<std::int32_t>(P.kind[i]);
  h5::write_dataset(fid, "kind", H5T_NATIVE_INT32, kind.data(), n, 1, tmp, rows);
  h5::write_dataset(fid, "id", H5T_NATIVE_UINT32, P.id.data(), n, 1, tmp, rows);
  // explicit Polyvertex connectivity: VTK's XDMF3 reader makes no cells without it
  const std::size_t first = rows && rows->collective ? rows->offset : 0;
  std::vector<std::int32_t> conn(n);
  for (std::size_t i = 0; i < n; ++i) conn[i] = static_cast<std::int32_t>(first + i);
  h5::write_dataset(fid, "connectivity", H5T_NATIVE_INT32, conn.data(), n, 1, tmp, rows);
  for (const auto& [fname, field] : P.scalar_fields())  // "_name": internal scratch (restart groups keep it)
    if (fname[0] != '_') h5::write_dataset(fid, fname, H5T_NATIVE_DOUBLE, field.data(), n, 1, tmp, rows);
  h5::write_attr(fid, "time", H5T_NATIVE_DOUBLE, &t, tmp);
  h5::write_attr(fid, "step", H5T_NATIVE_LONG, &step, tmp);
  const int dim = D;
  h5::write_attr(fid, "dimension", H5T_NATIVE_INT, &dim, tmp);
  if (rs) write_restart_group<D>(fid, P, *rs, tmp, rows);
}

/// The core driver's buffer, followed through HDF5's file image callbacks: the file is written from that buffer
/// itself. (H5Fget_file_image copies it: a second whole file in memory, 156 B per particle of a 3D snapshot.)
struct CoreImage {
  void* mem = nullptr;
  std::size_t size = 0;
};

H5FD_file_image_callbacks_t core_image_callbacks(CoreImage& img) {
  H5FD_file_image_callbacks_t cb{};
  cb.image_malloc = [](size_t size, H5FD_file_image_op_t op, void* ud) -> void* {
    void* p = std::malloc(size);
    if (op == H5FD_FILE_IMAGE_OP_FILE_OPEN && p) *static_cast<CoreImage*>(ud) = {p, size};
    return p;
  };
  cb.image_memcpy = [](void* dest, const void* src, size_t size, H5FD_file_image_op_t, void*) -> void* {
    return std::memcpy(dest, src, size);
  };
  cb.image_realloc = [](void* ptr, size_t size, H5FD_file_image_op_t op, void* ud) -> void* {
    void* p = std::realloc(ptr, size);
    auto& img = *static_cast<CoreImage*>(ud);
    if (p && (op == H5FD_FILE_IMAGE_OP_FILE_RESIZE || ptr == img.mem)) img = {p, size};
    return p;
  };
  cb.image_free = [](void* ptr, H5FD_file_image_op_t, void* ud) -> herr_t {
    auto& img = *static_cast<CoreImage*>(ud);
    if (ptr == img.mem) img = {};
    std::free(ptr);
    return 0;
  };
  cb.udata_copy = [](void* ud) -> void* { return ud; };  // (the property lists share the one record)
  cb.udata_free = [](void*) -> herr_t { return 0; };
  cb.udata = &img;
  return cb;
}

/// Write one particle file (fields, attributes, optional /restart group) to `tmp`.
/// HDF5 builds the file in memory (core driver, no backing store) and we write the image
/// ourselves: a full disk is then an ordinary failed write, which HDF5 1.10 does not survive
/// cleanly when it meets it itself (the library crashed at exit on a file whose close failed).
template <int D>
void write_particles(const std::string& tmp, const ParticleStore<D>& P, double t, long step, const RunState* rs) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // we report errors ourselves
  CoreImage img;
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_core(fapl, 1 << 20, 0);
  auto cb = core_image_callbacks(img);
  const bool tracked = H5Pset_file_image_callbacks(fapl, &cb) >= 0;
  h5::File f{H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl)};
  H5Pclose(fapl);
  if (f.id < 0) throw IoError(fmt::format("HDF5: cannot create '{}' in memory", tmp));
  write_contents<D>(f.id, tmp, P, t, step, rs, nullptr);
  if (H5Fflush(f.id, H5F_SCOPE_GLOBAL) < 0) throw IoError(fmt::format("HDF5: cannot finish '{}' in memory", tmp));
  const ssize_t size = H5Fget_file_image(f.id, nullptr, 0);
  if (size <= 0) throw IoError(fmt::format("HDF5: cannot get the image of '{}'", tmp));
  std::vector<char> copy;  // (only where the driver's buffer was not followed)
  const char* image = static_cast<const char*>(img.mem);
  if (!tracked || !image || img.size < static_cast<std::size_t>(size)) {
    copy.resize(static_cast<std::size_t>(size));
    if (H5Fget_file_image(f.id, copy.data(), copy.size()) != size) throw IoError(fmt::format("HDF5: cannot get the image of '{}'", tmp));
    image = copy.data();
  }
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError(fmt::format("cannot create '{}': {} (folder missing, no permission?)", tmp, std::strerror(errno)));
  out.write(image, static_cast<std::streamsize>(size));
  out.flush();
  if (!out) throw IoError(fmt::format("writing '{}' failed (disk full?): {}", tmp, std::strerror(errno)));
  out.close();
  if (!out) throw IoError(fmt::format("closing '{}' failed (disk full?): {}", tmp, std::strerror(errno)));
}

/// The same file written by every rank together (parallel HDF5: MPI-IO, collective transfers):
/// each rank its own particles, as a block of rows after those of the ranks before it. A
/// failure on one rank is a failure of the run (every rank is then stopped), and the temporary
/// file is left under its .tmp name, which nothing reads as a snapshot.
template <int D>
void write_particles_together(const std::string& tmp, const ParticleStore<D>& P, double t, long step, const RunState* rs,
                              const Communicator& comm) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  h5::Rows rows;
  rows.collective = true;
  std::uint64_t total = 0;
  rows.offset = comm.exscan(P.n_owned(), total);
  rows.total = total;
  rows.root = comm.root();
  rows.comm = &comm;
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  rows.dxpl = H5Pcreate(H5P_DATASET_XFER);
  struct Plists { hid_t a, b; ~Plists() { H5Pclose(a); H5Pclose(b); } } plists{fapl, rows.dxpl};
  if (!comm.parallel_hdf5(fapl, rows.dxpl)) throw IoError(fmt::format("HDF5: no parallel (MPI-IO) access for '{}'", tmp));
  h5::File f{H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl)};
  if (f.id < 0) throw IoError(fmt::format("HDF5: cannot create '{}' (folder missing, no permission?)", tmp));
  write_contents<D>(f.id, tmp, P, t, step, rs, &rows);
  const hid_t id = f.id;
  f.id = -1;
  if (H5Fclose(id) < 0) throw IoError(fmt::format("HDF5: cannot finish '{}' (disk full?)", tmp));
}

/// Run a writer on `tmp`; on failure remove the partial file, so that nothing half-written stays.
template <class Fn>
void write_or_clean(const std::string& tmp, Fn&& fn) {
  try {
    fn();
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void rename_into_place(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw IoError(fmt::format("cannot rename '{}' to '{}': {}", tmp, path, ec.message()));
}

}  // namespace

template <int D>
SnapshotWriter<D>::SnapshotWriter(std::string dir, std::shared_ptr<const Communicator> comm)
    : dir_(std::move(dir)), comm_(std::move(comm)) {
  if (comm_ && comm_->size() > 1) {  // (the same answer on every rank: one build, one library)
    const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    collective_ = comm_->parallel_hdf5(fapl, -1);
    H5Pclose(fapl);
  }
}

template <int D>
void SnapshotWriter<D>::write_file(const std::string& tmp, const ParticleStore<D>& P, double t, long step,
                                   const RunState* rs) const {
  if (collective_) {
    write_particles_together<D>(tmp, P, t, step, rs, *comm_);
    return;
  }
  write_or_clean(tmp, [&] { write_particles<D>(tmp, P, t, step, rs); });
}

template <int D>
std::string SnapshotWriter<D>::write(const ParticleStore<D>& P, double t, long step, const RunState* rs) {
  const std::string name = fmt::format("snap_{:06d}.h5", entries_.size());
  const std::string rel = "snapshots/" + name;
  const std::string path = dir_ + "/" + rel, tmp = path + ".tmp";
  std::error_code ec;
  fs::create_directories(dir_ + "/snapshots", ec);  // (every rank of a collective write: none may open first)
  if (ec) throw IoError(fmt::format("cannot create '{}/snapshots': {}", dir_, ec.message()));
  std::uint64_t total = P.n_owned();
  if (collective_) comm_->exscan(P.n_owned(), total);
  SnapshotEntry e{rel, t, static_cast<std::size_t>(total), {}};
  for (const auto& [fname, field] : P.scalar_fields())
    if (fname[0] != '_') e.scalars.push_back(fname);
  if (rs) {  // the series in the file includes this snapshot
    RunState r = *rs;
    r.snapshots = entries_;
    r.snapshots.push_back(e);
    write_file(tmp, P, t, step, &r);
  } else {
    write_file(tmp, P, t, step, nullptr);
  }
  const bool root = !comm_ || comm_->root();
  if (root) rename_into_place(tmp, path);
  entries_.push_back(e);
  if (root) write_xdmf();
  return path;
}

template <int D>
void SnapshotWriter<D>::write_checkpoint(const std::string& path, const ParticleStore<D>& P, const RunState& rs) const {
  const std::string tmp = path + ".tmp";
  write_file(tmp, P, rs.time, rs.step, &rs);
  if (!comm_ || comm_->root()) rename_into_place(tmp, path);
}

template <int D>
void SnapshotWriter<D>::resume(const std::vector<SnapshotEntry>& entries) {
  entries_ = entries;
  if (comm_ && !comm_->root()) return;  // (the first rank tidies the folder)
  std::error_code ec;
  if (fs::exists(dir_ + "/snapshots"))
    for (const auto& e : fs::directory_iterator(dir_ + "/snapshots", ec)) {
      const std::string name = e.path().filename().string();
      bool keep = false;
      for (const auto& k : entries_) keep |= (k.file == "snapshots/" + name);
      if (!keep && (e.path().extension() == ".h5" || e.path().extension() == ".tmp")) fs::remove(e.path(), ec);
    }
  write_xdmf();
}

template <int D>
std::string SnapshotWriter<D>::last_path() const {
  return entries_.empty() ? std::string() : dir_ + "/" + entries_.back().file;
}

template <int D>
void SnapshotWriter<D>::write_xdmf() const {
  std::string x;
  x += "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"3.0\">\n <Domain>\n";
  x += "  <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& e : entries_) {
    auto item = [&](const char* ds, int cols, const char* type, int prec) {
      return fmt::format("      <DataItem Dimensions=\"{}{}\" NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{}:/{}</DataItem>\n",
                         e.n, cols > 1 ? fmt::format(" {}", cols) : "", type, prec, e.file, ds);
    };
    x += fmt::format("   <Grid Name=\"t={:.9g}\" GridType=\"Uniform\">\n    <Time Value=\"{:.12g}\"/>\n", e.time, e.time);
    x += fmt::format("    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" NodesPerElement=\"1\">\n", e.n);
    x += item("connectivity", 1, "Int", 4) + "    </Topology>\n";
    x += "    <Geometry GeometryType=\"XYZ\">\n" + item("position", 3, "Float", 8) + "    </Geometry>\n";
    auto attr = [&](const std::string& name, const char* atype, int cols, const char* type, int prec) {
      x += fmt::format("    <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n", name, atype);
      x += item(name.c_str(), cols, type, prec);
      x += "    </Attribute>\n";
    };
    attr("velocity", "Vector", 3, "Float", 8);
    attr("pressure", "Scalar", 1, "Float", 8);
    attr("density", "Scalar", 1, "Float", 8);
    attr("mass", "Scalar", 1, "Float", 8);
    attr("kind", "Scalar", 1, "Int", 4);
    attr("id", "Scalar", 1, "UInt", 4);
    for (const auto& s : e.scalars) attr(s, "Scalar", 1, "Float", 8);
    x += "   </Grid>\n";
  }
  x += "  </Grid>\n </Domain>\n</Xdmf>\n";
  write_file_atomically(dir_ + "/particles.xdmf", x);
}

template class SnapshotWriter<2>;
template class SnapshotWriter<3>;

}  // namespace sph
