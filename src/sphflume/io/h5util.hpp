// Small HDF5 helpers shared by the snapshot and restart writers/readers (internal).
// Writers throw IoError naming the file; readers throw InputError (a restart file is input).
#pragma once
#include <hdf5.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sphflume/core/communicator.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/io/snapshot.hpp"

namespace sph::h5 {

struct File {
  hid_t id;
  ~File() { if (id >= 0) H5Fclose(id); }
};

inline void check(herr_t st, const std::string& what, const std::string& path) {
  if (st < 0)
    throw IoError(fmt::format("HDF5: cannot write {} to '{}' (disk full or no permission?): {}", what, path,
                              std::strerror(errno)));
}

/// The rows of a dataset this process writes. By default all of them (one process writes the
/// file). In a file written by every rank together (parallel HDF5, MPI-IO), a dataset has
/// `total` rows and this rank writes its block from `offset`; text (one copy, the same on every
/// rank) is the first rank's, written by it alone. Every rank makes the same calls in the same
/// order with the same dataset shapes (or parallel HDF5 waits forever in the file's close).
struct Rows {
  bool collective = false;
  hsize_t total = 0, offset = 0;
  hid_t dxpl = H5P_DEFAULT;  // collective transfers
  bool root = true;
  const Communicator* comm = nullptr;
};

inline void write_dataset(hid_t f, const std::string& name, hid_t type, const void* data, hsize_t n, hsize_t cols,
                          const std::string& path, const Rows* rows = nullptr) {
  const bool coll = rows && rows->collective;
  hsize_t dims[2] = {coll ? rows->total : n, cols};
  const int rank = cols > 1 ? 2 : 1;
  const hid_t space = H5Screate_simple(rank, dims, nullptr);
  const hid_t ds = H5Dcreate2(f, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (ds < 0) { H5Sclose(space); throw IoError(fmt::format("HDF5: cannot create dataset {} in '{}'", name, path)); }
  herr_t st = 0;
  if (coll) {  // this rank's block of rows (possibly none: every rank takes part in the write)
    hsize_t start[2] = {rows->offset, 0}, count[2] = {n, cols};
    const hid_t mem = H5Screate_simple(rank, count, nullptr);
    if (n > 0) H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr);
    else { H5Sselect_none(space); H5Sselect_none(mem); }
    st = rows->total > 0 ? H5Dwrite(ds, type, mem, space, rows->dxpl, data) : 0;
    H5Sclose(mem);
  } else {
    st = n > 0 ? H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0;
  }
  H5Dclose(ds);
  H5Sclose(space);
  check(st, name, path);
}

inline void write_attr(hid_t f, const char* name, hid_t type, const void* v, const std::string& path) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t st = a >= 0 ? H5Awrite(a, type, v) : -1;
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  check(st, name, path);
}

/// Text as a 1-D dataset of bytes (h5py: bytes(f[name][:]).decode()).
inline void write_text(hid_t f, const std::string& name, const std::string& text, const std::string& path,
                       const Rows* rows = nullptr) {
  if (rows && rows->collective) {  // (its length from the first rank: the shape must agree everywhere)
    Rows one = *rows;
    one.total = static_cast<hsize_t>(rows->comm->max(rows->root ? static_cast<double>(text.size()) : 0.0));
    one.offset = 0;
    write_dataset(f, name, H5T_NATIVE_UCHAR, text.data(), rows->root ? text.size() : 0, 1, path, &one);
    return;
  }
  write_dataset(f, name, H5T_NATIVE_UCHAR, text.data(), text.size(), 1, path);
}

inline bool exists(hid_t f, const std::string& name) { return H5Lexists(f, name.c_str(), H5P_DEFAULT) > 0; }

/// Read a dataset of n rows x cols columns; throws InputError when it is missing or mis-shaped.
template <class T>
std::vector<T> read_dataset(hid_t f, const std::string& name, hid_t type, std::size_t cols, const std::string& path,
                            long long expect_rows = -1) {
  if (!exists(f, name)) throw InputError(fmt::format("{}: dataset '{}' is missing", path, name));
  const hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  hsize_t dims[2] = {0, 1};
  const int rank = H5Sget_simple_extent_dims(space, dims, nullptr);
  H5Sclose(space);
  if (rank < 1 || rank > 2 || (rank == 2 && dims[1] != cols) || (rank == 1 && cols != 1) ||
      (expect_rows >= 0 && dims[0] != static_cast<hsize_t>(expect_rows))) {
    H5Dclose(ds);
    throw InputError(fmt::format("{}: dataset '{}' has an unexpected shape", path, name));
  }
  std::vector<T> out(dims[0] * cols);
  const herr_t st = dims[0] > 0 ? H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) : 0;
  H5Dclose(ds);
  if (st < 0) throw InputError(fmt::format("{}: cannot read dataset '{}' (truncated file?)", path, name));
  return out;
}

inline std::string read_text(hid_t f, const std::string& name, const std::string& path) {
  const auto b = read_dataset<unsigned char>(f, name, H5T_NATIVE_UCHAR, 1, path);
  return std::string(b.begin(), b.end());
}

template <class T>
T read_attr(hid_t f, const char* name, hid_t type, const std::string& path) {
  if (H5Aexists(f, name) <= 0) throw InputError(fmt::format("{}: attribute '{}' is missing", path, name));
  const hid_t a = H5Aopen(f, name, H5P_DEFAULT);
  T v{};
  const herr_t st = H5Aread(a, type, &v);
  H5Aclose(a);
  if (st < 0) throw InputError(fmt::format("{}: cannot read attribute '{}'", path, name));
  return v;
}

}  // namespace sph::h5
