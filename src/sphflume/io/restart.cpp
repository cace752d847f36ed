#include "sphflume/io/restart.hpp"

#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "sphflume/io/h5util.hpp"

namespace sph {
namespace {

// Doubles as hexadecimal floats: exact round trip.
std::string hexd(double v) { return fmt::format("{:a}", v); }
double parse_d(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

std::string counters_text(const RunState& rs) {
  std::string t;
  t += "time=" + hexd(rs.time) + "\n";
  t += fmt::format("step={}\n", rs.step);
  t += "next_output=" + hexd(rs.next_output) + "\n";
  t += "dt_first=" + hexd(rs.dt_first) + "\n";
  t += "initial_mass=" + hexd(rs.initial_mass) + "\n";
  t += "removed_mass=" + hexd(rs.removed_mass) + "\n";
  for (const auto& [f, n] : rs.removed_by_face) t += fmt::format("removed.{}={}\n", f, n);
  for (const auto& [f, m] : rs.removed_mass_by_face) t += "removed_mass." + f + "=" + hexd(m) + "\n";
  t += "inflow_mass=" + hexd(rs.open.inflow_mass) + "\n";
  t += "outflow_mass=" + hexd(rs.open.outflow_mass) + "\n";
  t += fmt::format("backflow={}\nnext_id={}\n", rs.open.backflow, rs.open.next_id);
  t += "backflow_mass=" + hexd(rs.open.backflow_mass) + "\n";
  if (rs.splits != 0 || rs.merges != 0) t += fmt::format("splits={}\nmerges={}\n", rs.splits, rs.merges);
  for (const auto& [k, v] : rs.scheme) t += "scheme." + k + "=" + hexd(v) + "\n";
  return t;
}

void parse_counters(const std::string& text, RunState& rs, const std::string& path) {
  std::istringstream in(text);
  bool have_time = false, have_step = false;
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string k = line.substr(0, eq), v = line.substr(eq + 1);
    if (k == "time") { rs.time = parse_d(v); have_time = true; }
    else if (k == "step") { rs.step = std::strtol(v.c_str(), nullptr, 10); have_step = true; }
    else if (k == "next_output") rs.next_output = parse_d(v);
    else if (k == "dt_first") rs.dt_first = parse_d(v);
    else if (k == "initial_mass") rs.initial_mass = parse_d(v);
    else if (k == "removed_mass") rs.removed_mass = parse_d(v);
    else if (k == "inflow_mass") rs.open.inflow_mass = parse_d(v);
    else if (k == "outflow_mass") rs.open.outflow_mass = parse_d(v);
    else if (k == "backflow") rs.open.backflow = std::strtol(v.c_str(), nullptr, 10);
    else if (k == "backflow_mass") rs.open.backflow_mass = parse_d(v);
    else if (k == "splits") rs.splits = std::strtol(v.c_str(), nullptr, 10);
    else if (k == "merges") rs.merges = std::strtol(v.c_str(), nullptr, 10);
    else if (k == "next_id") rs.open.next_id = static_cast<std::uint32_t>(std::strtoul(v.c_str(), nullptr, 10));
    else if (k.rfind("removed_mass.", 0) == 0) rs.removed_mass_by_face[k.substr(13)] = parse_d(v);
    else if (k.rfind("removed.", 0) == 0) rs.removed_by_face[k.substr(8)] = std::strtol(v.c_str(), nullptr, 10);
    else if (k.rfind("scheme.", 0) == 0) rs.scheme[k.substr(7)] = parse_d(v);
  }
  if (!have_time || !have_step) throw InputError(fmt::format("{}: /restart/counters lacks time or step", path));
}

std::string index_text(const std::vector<SnapshotEntry>& entries) {
  std::string t;
  for (const auto& e : entries) {
    std::string sc;
    for (const auto& s : e.scalars) sc += (sc.empty() ? "" : ",") + s;
    t += fmt::format("{}\t{}\t{}\t{}\n", e.file, hexd(e.time), e.n, sc);
  }
  return t;
}

std::vector<SnapshotEntry> parse_index(const std::string& text) {
  std::vector<SnapshotEntry> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    SnapshotEntry e;
    std::string t, n, sc;
    if (!std::getline(ls, e.file, '\t') || !std::getline(ls, t, '\t') || !std::getline(ls, n, '\t')) continue;
    std::getline(ls, sc);
    e.time = parse_d(t);
    e.n = std::strtoul(n.c_str(), nullptr, 10);
    std::istringstream ss(sc);
    for (std::string s; std::getline(ss, s, ',');) if (!s.empty()) e.scalars.push_back(s);
    out.push_back(e);
  }
  return out;
}

}  // namespace

template <int D>
void write_restart_group(long long file_id, const ParticleStore<D>& P, const RunState& rs, const std::string& path,
                         const h5::Rows* rows) {
  const hid_t f = static_cast<hid_t>(file_id);
  const hid_t g = H5Gcreate2(f, "restart", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (g < 0) throw IoError(fmt::format("HDF5: cannot create group /restart in '{}'", path));
  struct Closer { hid_t g; ~Closer() { H5Gclose(g); } } closer{g};
  const std::size_t n = P.n_owned();
  h5::write_dataset(g, "acc", H5T_NATIVE_DOUBLE, P.acc.data(), n, D, path, rows);
  h5::write_dataset(g, "drho", H5T_NATIVE_DOUBLE, P.drho.data(), n, 1, path, rows);
  for (const auto& [name, v] : P.vector_fields()) h5::write_dataset(g, "vector_" + name, H5T_NATIVE_DOUBLE, v.data(), n, D, path, rows);
  for (const auto& [name, v] : P.scalar_fields()) h5::write_dataset(g, "scalar_" + name, H5T_NATIVE_DOUBLE, v.data(), n, 1, path, rows);
  h5::write_text(g, "case", rs.case_text, path, rows);
  h5::write_text(g, "counters", counters_text(rs), path, rows);
  h5::write_text(g, "snapshot_index", index_text(rs.snapshots), path, rows);
}

template <int D>
void read_restart(const std::string& path, ParticleStore<D>& P, RunState& rs) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("--restart {}: no such file", path));
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  h5::File f{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)};
  if (f.id < 0) throw InputError(fmt::format("--restart {}: not an HDF5 file, or a truncated one", path));
  const int dim = h5::read_attr<int>(f.id, "dimension", H5T_NATIVE_INT, path);
  if (dim != D) throw InputError(fmt::format("--restart {}: written by a {}D run, the case is {}D", path, dim, D));
  if (!h5::exists(f.id, "restart"))
    throw InputError(fmt::format("--restart {}: this snapshot holds no restart data (/restart): it was written by an "
                                 "older version; restart from a newer snapshot or run again", path));
  // one dataset at a time into the store, each freed before the next is read: the peak is the store and one
  // field (the whole file's arrays at once held 112 B per 3D particle beside it)
  const auto nid = h5::read_dataset<std::uint32_t>(f.id, "id", H5T_NATIVE_UINT32, 1, path);
  const long long n = static_cast<long long>(nid.size());
  const auto count = static_cast<std::size_t>(n);
  rs = RunState{};
  parse_counters(h5::read_text(f.id, "restart/counters", path), rs, path);
  rs.case_text = h5::read_text(f.id, "restart/case", path);
  rs.snapshots = parse_index(h5::read_text(f.id, "restart/snapshot_index", path));

  // the extra fields: every dataset of /restart named scalar_* or vector_*
  std::vector<std::string> names;
  {
    const hid_t g = H5Gopen2(f.id, "restart", H5P_DEFAULT);
    H5Literate(g, H5_INDEX_NAME, H5_ITER_INC, nullptr,
                [](hid_t, const char* name, const H5L_info_t*, void* op) -> herr_t {
                  static_cast<std::vector<std::string>*>(op)->push_back(name);
                  return 0;
                },
                &names);
    H5Gclose(g);
  }

  P = ParticleStore<D>{};
  {
    const auto kind = h5::read_dataset<std::int32_t>(f.id, "kind", H5T_NATIVE_INT32, 1, path, n);
    P.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
      if (kind[i] < 0 || kind[i] >= kKindCount) throw InputError(fmt::format("{}: particle {} has an unknown kind {}", path, i, kind[i]));
      P.add(Vec<D>{}, Vec<D>{}, 0.0, 0.0, static_cast<Kind>(kind[i]));
    }
  }
  std::copy(nid.begin(), nid.end(), P.id.begin());
  auto vectors = [&](const char* name, int cols, std::vector<Vec<D>>& to) {  // (files hold 3 columns, restart/ D)
    const auto v = h5::read_dataset<double>(f.id, name, H5T_NATIVE_DOUBLE, static_cast<std::size_t>(cols), path, n);
    for (std::size_t i = 0; i < count; ++i) {
      const double* x = v.data() + std::size_t(cols) * i;
      if (cols == 3) {
        to[i][0] = x[0];
        if constexpr (D == 3) to[i][1] = x[1];
        to[i][D - 1] = x[2];
      } else {
        for (int d = 0; d < D; ++d) to[i][d] = x[d];
      }
    }
  };
  auto scalars = [&](const std::string& name, std::vector<double>& to) {
    const auto v = h5::read_dataset<double>(f.id, name, H5T_NATIVE_DOUBLE, 1, path, n);
    std::copy(v.begin(), v.end(), to.begin());
  };
  vectors("position", 3, P.pos);
  vectors("velocity", 3, P.vel);
  scalars("pressure", P.p);
  scalars("density", P.rho);
  scalars("mass", P.mass);
  vectors("restart/acc", D, P.acc);
  scalars("restart/drho", P.drho);
  for (const auto& name : names) {
    if (name.rfind("scalar_", 0) == 0) scalars("restart/" + name, P.scalar(name.substr(7)));
    else if (name.rfind("vector_", 0) == 0) vectors(("restart/" + name).c_str(), D, P.vector(name.substr(7)));
  }
  P.shrink_to_fit();
}

template void write_restart_group<2>(long long, const ParticleStore<2>&, const RunState&, const std::string&, const h5::Rows*);
template void write_restart_group<3>(long long, const ParticleStore<3>&, const RunState&, const std::string&, const h5::Rows*);
template void read_restart<2>(const std::string&, ParticleStore<2>&, RunState&);
template void read_restart<3>(const std::string&, ParticleStore<3>&, RunState&);

}  // namespace sph
