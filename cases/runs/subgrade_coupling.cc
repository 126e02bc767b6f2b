#include "cases/runs/subgrade_coupling.h"

#include <mpi.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>

#include "common/input_error.h"

namespace trackbed::cases {

namespace fs = std::filesystem;
using dem::Vec3;

namespace {

std::string fem_frame_file(int k) {
  char name[64];
  std::snprintf(name, sizeof name, "fem/fem_%05d.pvtu", k);
  return name;
}

std::string interface_frame_file(int k) {
  char name[64];
  std::snprintf(name, sizeof name, "vtu/interface-%06d.vtu", k);
  return name;
}

}  // namespace

SubgradeCoupling::SubgradeCoupling(const CaseParameters& prm, const TrackSection& section)
    : out_(prm.output_folder), parameters_(prm.coupling) {
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  parameters_.validate();
  subgrade_ = std::make_unique<coupling::Subgrade>(section, prm.subgrade, MPI_COMM_WORLD);
  const dem::TriangleMesh& wall = subgrade_->wall().mesh();
  vertex_area_.assign(wall.vertices.size(), 0.0);
  for (const auto& t : wall.triangles) {
    const double area = 0.5 * (wall.vertices[t[1]] - wall.vertices[t[0]])
                                  .cross(wall.vertices[t[2]] - wall.vertices[t[0]])
                                  .norm();
    for (int v : t) vertex_area_[v] += area / 3;
  }
}

SubgradeCoupling::~SubgradeCoupling() {
  if (leader() && !released_) announce(Command::finish);
}

std::string SubgradeCoupling::description() const {
  int processes = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &processes);
  fem::ElasticBody& body = subgrade_->body();
  return "FE subgrade of " + std::to_string(body.n_cells()) + " cells, " +
         std::to_string(body.n_dofs()) + " degrees of freedom on " + std::to_string(processes) +
         " MPI process" + (processes > 1 ? "es" : "") + "; formation wall of " +
         std::to_string(vertex_area_.size()) + " vertices; an exchange every " +
         std::to_string(parameters_.interval_steps) + " DEM steps";
}

dem::MeshBody SubgradeCoupling::formation_body(int material) const {
  dem::MeshBody body = dem::MeshBody::from_world_mesh("formation", subgrade_->wall().mesh(),
                                                      material, 0, Vec3::Zero());
  body.make_deformable();
  return body;
}

void SubgradeCoupling::announce(Command command, int argument) {
  std::array<int, 2> message{{static_cast<int>(command), argument}};
  MPI_Bcast(message.data(), 2, MPI_INT, 0, MPI_COMM_WORLD);
}

void SubgradeCoupling::serve() {
  while (true) {
    std::array<int, 2> message{};
    MPI_Bcast(message.data(), 2, MPI_INT, 0, MPI_COMM_WORLD);
    switch (static_cast<Command>(message[0])) {
      case Command::finish:
        return;
      case Command::start:
        scheme_ = std::make_unique<coupling::QuasiStaticScheme>(subgrade_->body(),
                                                                subgrade_->wall(), parameters_);
        break;
      case Command::exchange:
        scheme_->exchange();
        break;
      case Command::frame:
        subgrade_->body().write_vtu(out_ + "/fem", "fem", message[1]);
        break;
      case Command::state:
        subgrade_->body().displacement_dofs();
        break;
      case Command::restore:
        restore(Progress());
        break;
    }
  }
}

void SubgradeCoupling::start(dem::Simulation& sim, int mesh, int sleeper, const std::string& out,
                             const Progress* progress, const std::vector<double>& frame_times) {
  sim_ = &sim;
  sleeper_ = sleeper;
  out_ = out;
  announce(Command::start);
  scheme_ = std::make_unique<coupling::QuasiStaticScheme>(sim, mesh, subgrade_->body(),
                                                          subgrade_->wall(), parameters_);
  interval_origin_.assign(vertex_area_.size(), Vec3::Zero());
  sleeper_z0_ = sleeper >= 0 ? sim.meshes()[sleeper].x.z() : 0.0;
  if (progress) {
    announce(Command::restore);
    restore(*progress);
  }
  open_outputs(progress, frame_times);
}

void SubgradeCoupling::open_outputs(const Progress* progress,
                                    const std::vector<double>& frame_times) {
  fs::create_directories(fs::path(out_) / "fem");
  const std::string h = out_ + "/history/";
  auto open = [&](const char* name, int k) {
    return progress ? std::make_unique<dem::AtomicFile>(h + name, progress->history_bytes[k])
                    : std::make_unique<dem::AtomicFile>(h + name);
  };
  interface_csv_ = open("interface.csv", 0);
  settlement_csv_ = open("settlement.csv", 1);
  for (auto* f : {interface_csv_.get(), settlement_csv_.get()})
    f->stream() << std::setprecision(12);
  std::vector<std::pair<double, std::string>> fem_frames, interface_frames;
  for (std::size_t k = 0; k < frame_times.size(); ++k) {
    fem_frames.emplace_back(frame_times[k], fem_frame_file(static_cast<int>(k)));
    interface_frames.emplace_back(frame_times[k], interface_frame_file(static_cast<int>(k)));
  }
  pvd_fem_ = std::make_unique<dem::PvdCollection>(out_ + "/fem.pvd", std::move(fem_frames));
  pvd_interface_ =
      std::make_unique<dem::PvdCollection>(out_ + "/interface.pvd", std::move(interface_frames));
  if (progress) return;
  interface_csv_->stream()
      << "time,exchange,ramp,dem_fx,dem_fy,dem_fz,fe_fx,fe_fy,fe_fz,balance_error,residual,"
         "work_residual,displacement,relaxation,converged,fe_iterations\n";
  settlement_csv_->stream() << "time,sleeper_settlement,formation_settlement_mean,"
                               "formation_settlement_max,interface_work,fe_strain_energy\n";
}

void SubgradeCoupling::after_step() {
  if (sim_->step_count() % parameters_.interval_steps == 0) exchange();
}

void SubgradeCoupling::exchange() {
  // Where the wall has arrived: the end of the interval whose mean loads the exchange takes.
  const std::vector<Vec3> arrived = scheme_->interface_displacement();
  announce(Command::exchange);
  try {
    last_ = scheme_->exchange();
  } catch (...) {
    released_ = true;  // every process failed the same collective check: none is waiting
    throw;
  }
  // The work of the bed on the subgrade over the interval: each mean vertex load times its
  // vertex's displacement over it (the wall moved at constant velocity). The FE body stores
  // f . U / 2 of the ramped load; over a converged quasi-static loading the two agree
  // (docs/coupling.md, "Interface energy").
  const std::vector<Vec3>& loads = scheme_->vertex_loads();
  for (std::size_t v = 0; v < loads.size(); ++v) {
    interface_work_ += loads[v].dot(arrived[v] - interval_origin_[v]);
    interval_origin_[v] = arrived[v];
  }
  strain_energy_ = 0.5 * last_.load_work;
  fe_seconds_ += last_.fe_seconds;
  write_histories(last_);
}

double SubgradeCoupling::mean_formation_settlement() const {
  const std::vector<Vec3>& u = scheme_->interface_displacement();
  double area = 0, sum = 0;
  for (std::size_t v = 0; v < u.size(); ++v) {
    area += vertex_area_[v];
    sum -= vertex_area_[v] * u[v].z();
  }
  return sum / area;
}

void SubgradeCoupling::write_histories(const coupling::ExchangeReport& r) {
  const double t = sim_->time();
  auto& i = interface_csv_->stream();
  i << t << "," << r.exchange << "," << r.ramp;
  for (const Vec3* f : {&r.dem_load, &r.fe_load})
    i << "," << f->x() << "," << f->y() << "," << f->z();
  i << "," << r.balance_error << "," << r.residual << "," << r.work_residual << ","
    << r.displacement << "," << r.relaxation << "," << (r.converged ? 1 : 0) << ","
    << r.fe_iterations << "\n";
  double largest = 0;
  for (const Vec3& u : scheme_->interface_displacement()) largest = std::max(largest, -u.z());
  const double sleeper = sleeper_ >= 0 ? sleeper_z0_ - sim_->meshes()[sleeper_].x.z() : NAN;
  settlement_csv_->stream() << t << "," << sleeper << "," << mean_formation_settlement() << ","
                            << largest << "," << interface_work_ << "," << strain_energy_ << "\n";
  interface_csv_->require_written();
  settlement_csv_->require_written();
}

void SubgradeCoupling::write_frame(int k, double time) {
  announce(Command::frame, k);
  subgrade_->body().write_vtu(out_ + "/fem", "fem", k);
  pvd_fem_->add(time, fem_frame_file(k));
  write_interface_frame(k);
  pvd_interface_->add(time, interface_frame_file(k));
}

void SubgradeCoupling::write_interface_frame(int k) {
  // The formation as the DEM sees it: its displacement, the last exchange's mean vertex loads,
  // and the traction they make (load over the vertex's share of the area).
  const dem::TriangleMesh& wall = subgrade_->wall().mesh();
  const std::vector<Vec3>& u = scheme_->interface_displacement();
  const std::vector<Vec3>& loads = scheme_->vertex_loads();
  dem::VtuGrid grid;
  dem::VtuGrid::Field displacement{"displacement", 3, {}}, load{"load", 3, {}},
      traction{"traction", 3, {}};
  for (std::size_t v = 0; v < wall.vertices.size(); ++v) {
    grid.points.push_back(wall.vertices[v] + u[v]);
    const Vec3 p = loads[v] / vertex_area_[v];
    for (int c = 0; c < 3; ++c) {
      displacement.values.push_back(u[v][c]);
      load.values.push_back(loads[v][c]);
      traction.values.push_back(p[c]);
    }
  }
  for (const auto& t : wall.triangles) {
    for (int v : t) grid.connectivity.push_back(v);
    grid.offsets.push_back(static_cast<std::int64_t>(grid.connectivity.size()));
    grid.types.push_back(5);
  }
  grid.point_data = {std::move(displacement), std::move(load), std::move(traction)};
  grid.write(out_ + "/" + interface_frame_file(k));
}

SubgradeCoupling::Progress SubgradeCoupling::progress() {
  announce(Command::state);
  Progress p;
  p.fe_displacement = subgrade_->body().displacement_dofs();
  p.scheme = scheme_->state();
  p.interval_origin = interval_origin_;
  p.history_bytes = {static_cast<long>(interface_csv_->flushed_size()),
                     static_cast<long>(settlement_csv_->flushed_size())};
  p.interface_work = interface_work_;
  p.strain_energy = strain_energy_;
  p.fe_seconds = fe_seconds_;
  p.sleeper_z0 = sleeper_z0_;
  return p;
}

void SubgradeCoupling::restore(const Progress& progress) {
  // The leader sends its checkpoint's FE state and scheme to every process; all restore them.
  std::vector<double> numbers = progress.fe_displacement;
  long count = static_cast<long>(numbers.size());
  MPI_Bcast(&count, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  numbers.resize(count);
  MPI_Bcast(numbers.data(), static_cast<int>(count), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  subgrade_->body().set_displacement_dofs(numbers);

  coupling::QuasiStaticState state = progress.scheme;
  std::array<double, 4> head{{double(state.exchanges), state.last_relaxation,
                              state.converged ? 1.0 : 0.0, double(state.diverging)}};
  MPI_Bcast(head.data(), 4, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  std::array<long, 2> sizes{{long(state.displacement.size()), long(state.last_residual.size())}};
  MPI_Bcast(sizes.data(), 2, MPI_LONG, 0, MPI_COMM_WORLD);
  state.displacement.resize(sizes[0]);
  state.last_residual.resize(sizes[1]);
  MPI_Bcast(state.displacement.data(), static_cast<int>(3 * sizes[0]), MPI_DOUBLE, 0,
            MPI_COMM_WORLD);
  MPI_Bcast(state.last_residual.data(), static_cast<int>(3 * sizes[1]), MPI_DOUBLE, 0,
            MPI_COMM_WORLD);
  state.exchanges = static_cast<int>(head[0]);
  state.last_relaxation = head[1];
  state.converged = head[2] != 0;
  state.diverging = static_cast<int>(head[3]);
  scheme_->restore(std::move(state));
  if (!leader()) return;
  if (progress.interval_origin.size() != vertex_area_.size())
    throw InputError("the coupling state has " + std::to_string(progress.interval_origin.size()) +
                     " formation vertices where the subgrade has " +
                     std::to_string(vertex_area_.size()) + "; valid: a checkpoint of this case");
  interval_origin_ = progress.interval_origin;
  interface_work_ = progress.interface_work;
  strain_energy_ = progress.strain_energy;
  fe_seconds_ = progress.fe_seconds;
  sleeper_z0_ = progress.sleeper_z0;
}

std::vector<SummaryItem> SubgradeCoupling::summary() const {
  return {
      {"fe_cells", "FE cells", "", double(subgrade_->body().n_cells())},
      {"fe_dofs", "FE degrees of freedom", "", double(subgrade_->body().n_dofs())},
      {"formation_vertices", "formation wall vertices", "", double(vertex_area_.size())},
      {"fe_solves", "FE solves (exchanges)", "", double(scheme_->exchanges())},
      {"coupling_converged", "coupling converged at the last exchange (1 yes)", "",
       scheme_->converged() ? 1.0 : 0.0},
      {"fe_coupling_seconds", "FE solves and coupling maps", "s", fe_seconds_},
      {"formation_settlement_mean_m", "mean formation settlement", "m",
       mean_formation_settlement()},
      {"sleeper_settlement_m", "sleeper settlement", "m",
       sleeper_ >= 0 ? sleeper_z0_ - sim_->meshes()[sleeper_].x.z() : NAN},
      {"interface_work_j", "work of the bed on the subgrade", "J", interface_work_},
      {"fe_strain_energy_j", "FE strain energy", "J", strain_energy_},
  };
}

void SubgradeCoupling::finish(bool sound) {
  // The other processes are released first: a history that cannot be written must not leave
  // them waiting.
  if (!released_) announce(Command::finish);
  released_ = true;
  for (dem::AtomicFile* f : {interface_csv_.get(), settlement_csv_.get()})
    if (sound || f->written()) f->commit();
}

}  // namespace trackbed::cases
