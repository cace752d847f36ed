// The plain configuration of a run: one struct per model (fluid, scheme, walls, shapes, gauges,
// open boundaries, turbulence, porous media, transport, phases) and the Case that holds them.
// Physics, boundaries and schemes read their options from these; they are filled by the case
// reader (io/case.*), or by hand in tests and programs that use the library without a case
// file. No YAML here.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sphflume/core/errors.hpp"
#include "sphflume/core/kernels.hpp"
#include "sphflume/core/node.hpp"
#include "sphflume/core/eos.hpp"
#include "sphflume/core/solid_mesh.hpp"

namespace sph {


enum class Integrator { Symplectic, PredictorCorrector, Verlet, Dual };
enum class DensityDiffusion { None, MolteniColagrossi, Fourtakas };
enum class ViscosityModel { None, Laminar, Artificial };
enum class PressureGradient { Sum, Symmetric };  // (pa+pb)/(ra rb) [Federico 3.8] ; pa/ra^2+pb/rb^2 [3.9]

/// Particle shifting's options (physics/shifting.hpp).
struct ShiftingConfig {
  double coefficient = 0.0;  // A; 0 = off (Skillen et al. 2013 suggest 1 to 6); constant: D/h² (Lind: 0.5)
  double surface = 0.0;      // ∇·r threshold of the free surface; 0 = 1.5 (2D) or 2.75 (3D); constant: 1.7 / 2.6
  // constant (Lind et al. 2012, the ISPH of Chow et al. 2018): δr = −D (∇C + R Σ V (W/W(dx))^n ∇W) with
  // D = coefficient h², the normal component removed below `surface`, |δr| ≤ cap dx
  bool constant = false;
  bool automatic = false;  // constant: coefficient = the kernel's stable one (Shifting::stable_coefficient)
  double tensile = 0.2, exponent = 4.0, cap = 0.2;
  bool on() const { return coefficient > 0.0; }
};

struct FluidConfig {
  double density = 1000.0;     // rho0 [kg/m3]
  double viscosity = 1.0e-6;   // kinematic nu [m2/s]
  double sound_speed = 0.0;    // c0 [m/s]; 0 = derived from reference_velocity
  double reference_velocity = 0.0;  // U for c0 = 10 U; 0 = sqrt(2 g H) from the fluid height
  EosType eos = EosType::Tait;
  double gamma = 7.0;
  double background_pressure = 0.0;
  bool hydrostatic_init = true;  // initial density from the hydrostatic pressure
};

struct SchemeConfig {
  std::string type = "wcsph";
  Integrator integrator = Integrator::Symplectic;  // symplectic | predictor_corrector | verlet | dual
  // dual (schemes/dual.hpp): acoustic steps cfl h/(c+|u|) inside advection steps
  // advection_cfl h/max(U, |u|, sqrt(4 h |a|)), U = c0/10; Riemann-solver pressure and continuity
  double advection_cfl = 0.25;
  double riemann_limiter = 3.0;   // slope of the low-dissipation limiter min(k U/c0, 1)
  bool density_reinit = true;     // density by summation (>= rho0) at every advection step
  bool pairs_per_advection = false;  // pairs: advection — each advection step's pairs and kernel gradients kept (SPHinXsys)
  bool half_sweep = true;  // pair_sweep: half — the rates pass visits each fluid pair once (half stencils); full: both ends
  int verlet_steps = 40;  // verlet: an Euler step every N steps (DualSPHysics VerletSteps)
  DensityDiffusion density_diffusion = DensityDiffusion::Fourtakas;
  double delta = 0.1;
  ViscosityModel viscosity = ViscosityModel::Laminar;
  double alpha = 0.01;  // Monaghan artificial viscosity
  double alpha_on_laminar = 0.0;  // not a case key: Monaghan's term beside the laminar one (ISPH's force pass)
  PressureGradient pressure_gradient = PressureGradient::Sum;
  int shepard_every = 0;  // 0 = never
  double xsph = 0.0;      // epsilon of XSPH; 0 = off
  ShiftingConfig shifting;  // particle shifting (physics/shifting.hpp); off by default
  double cfl = 0.2;       // dt <= cfl * h / (c_max + |u|_max)
  double viscous_coefficient = 0.125;  // dt <= coef * h^2 / nu
  double force_coefficient = 0.25;     // dt <= coef * sqrt(h / |a|_max)
  double eta2 = 0.01;  // η²/h² regularising 1/(r²+η²) in viscous and diffusion terms (theses: 0.01)
  bool frozen = false;  // the flow is not integrated (particles fixed): only scalars are transported
  bool pressure = true;  // not a case key: false = the pair loop without pressure (ISPH's force pass)
};

/// The projection scheme's options (`scheme.type: isph`, schemes/isph.hpp; read by
/// schemes/isph_options.cpp).
enum class PpeSource { Hybrid, Standard, DivergenceFree, Split };
// the projection scheme's formulation: Lind, Skillen and Chow's (schemes/isph_projection.hpp) or
// Tsurudome's (schemes/isph.hpp), docs/numerics.md §13
enum class IsphFormulation { Lind, Tsurudome };

struct IsphConfig {
  IsphFormulation formulation = IsphFormulation::Lind;  // the default since issue 57 (docs/numerics.md §13)
  double correction_min_eigenvalue = 0.25;  // lind: the kernel-gradient correction's eigenvalue floor
  double fs_blend = 0.2;             // lind: Skillen's blend of the PPE over ∇·r ∈ [threshold, threshold + blend]
  bool laplacian_corrected = true;   // lind: the PPE's Laplacian corrected to first order (`laplacian: corrected`)
  bool wall_adami = false;           // lind: walls' pressure by Adami et al. (2012)'s extrapolation, not the mirror points
  double volume_correction = 0.0;    // lind: ω of the weak volume correction on full-support particles
  bool clamp_negative = false;       // lind: the fluid's pressure held at ≥ 0 after the solve (no tension)
  bool fs_at_surface = true;         // lind: P = 0 at the surface, dx/2 beyond a surface particle (a Robin row),
                                     // instead of on the surface particles' centres (free_surface.condition)
  double cfl = 0.2;                  // dt <= cfl dx / |u|max (Tsurudome §3.6, eq 3.6.6: the particle spacing, not h)
  double force_coefficient = 0.25;   // dt <= coef sqrt(h / |a|max), |a| at least |g|
  double viscous_coefficient = 0.125;// dt <= coef h^2 / (nu + nu_t)
  double dt_max = 0.0;               // 0: no cap beyond the limits above
  double eta2 = 0.01;                // η²/h² in 1/(r² + η²) (Laplacian and viscous term)
  bool viscosity = true;             // a viscous term (laminar and/or artificial); false = inviscid
  bool laminar = true;               // the laminar (Lo & Shao) term (viscosity: laminar)
  double alpha = 0.02;               // Monaghan's artificial viscosity beside the laminar term, with the
                                     // reference sound speed c0 (PySPH's SISPH: 0.05); 0 = none
  // hybrid (default): Tsurudome's γ div-free + (1 − γ) density-invariant source in one pressure; split:
  // the pressure from the divergence-free source alone, the density error corrected by a second solve
  // that moves the particles (δr = −Δt² ∇ψ/ρ, a fraction `relaxation` of the error per step)
  PpeSource source = PpeSource::Hybrid;
  double gamma = 0.97;               // hybrid source: γ div-free + (1 − γ) density-invariant
  double relaxation = 0.1;           // split source: the fraction of the density error corrected per step
  bool density_deficit = true;       // the density-invariant part acts on deficits too (the thesis)
  bool fs_divergence = false;        // free surface by ∇·r < threshold (Lee et al. 2008) instead of the density
  bool gradient_lattice = false;     // the pressure gradient divided by its lattice moment κ (not in the thesis)
  // dummy wall particles: P of the first-layer particle at the foot of their normal (copy: the
  // thesis's homogeneous Neumann condition) plus ρ0 (g − a_w)·(x_dummy − x_foot) (body_force: the
  // Neumann condition ∂P/∂n = ρ (g − a_w)·n of a wall accelerating at a_w, as Adami's dummies)
  bool dummy_body_force = false;
  double fs_threshold = 0.99;        // density: ρ_sum < threshold ρ_ref (Tsurudome eq 4.2.3; thesis 1.0);
                                     // divergence: 1.5 (2D), 2.4 (3D) unless given
  double tolerance = 1e-6;           // the PPE's relative residual
  int max_iterations = 2000;
  bool amg = false;                  // solver.type: boomeramg (hypre) instead of bicgstab (Eigen)
  bool solver_auto = true;           // solver.type: auto (default): boomeramg from kAutoAmgUnknowns unknowns when hypre is built in
  ShiftingConfig shifting;           // particle shifting after the step (off by default, as in the thesis)
  std::vector<std::string> ignored;  // WCSPH keys given here: "line N: scheme.KEY"
};

/// Eddy-viscosity turbulence (Kazemi ch. 3 and 6): nu_t from the strain rate |S| of the
/// particle velocity field, stress tau = 2 rho nu_t S_dev added to the momentum equation.
struct TurbulenceConfig {
  std::string model = "none";  // none | smagorinsky | mixing_length
  double cs = 0.15;            // smagorinsky: nu_t = (cs delta)^2 |S|
  double delta = 0.0;          // smagorinsky filter width [m]; 0 = dx
  bool strain_literal = false; // |S| = sqrt(S:S) (Kazemi eq 2.17 as printed) instead of sqrt(2 S:S)
  // mixing_length: nu_t = l_m^2 |S|
  std::string profile = "nezu_rodi";  // nezu_rodi | three_layer | constant
  double bed = 0.0;            // z of the numerical bed (z_w = z - bed) [m]
  double kappa = 0.41;         // nezu_rodi: von Karman constant
  double coles_pi = 0.0;       // nezu_rodi: wake strength Pi
  bool van_driest = false;     // nezu_rodi: damping 1 - exp(-z+/A+), u* = sqrt(g_x H) (uniform flow)
  double a_plus = 26.0;
  double length = 0.0;         // constant: l_m [m]
  // three_layer (Kazemi eq 6.7): levels in m, in the case's frame
  double z_trough = 0.0, z_crest = 0.0, l_mb = 0.002, dz0 = 0.0, kappa_r = 0.27, kappa_f = 0.22;
  double column_width = 0.0;   // free-surface columns [m]; 0 = 2 dx
  int line = 0;
};

struct WallConfig {
  std::string type = "dummy";  // dummy (Adami 2012) | dynamic (SPHysics)
  bool no_slip = true;
  int layers = 0;  // 0 = derived from the kernel support
  bool clamp_negative_pressure = true;
  // Monaghan & Kos (1999) normal repulsive force from wall particles within dx (Federico §5.2.1c,
  // eqs 5.3-5.5), alone (type repulsive) or added to another wall model (Federico §5.2.5 couples
  // it with ghost particles)
  bool repulsive = false;
  double beta1 = 0.01, beta2 = 1.0;  // A5 = (beta1 c0² + beta2 c0 v_approach) / h (Federico ch. 6 values)
  // Backup against penetration (any model but repulsive): a fluid particle closer than dx/4 to the
  // wall surface (through a first-layer wall particle's tangent plane) is pushed back out; inert
  // while the wall model keeps the fluid at its normal dx/2 from the surface (WallModel::add_forces)
  bool backup = true;
  // fixed_ghost: tangential ghost velocity = psi × the interpolated one (Federico eq 5.8: psi in
  // [0, 1] calibrates bed roughness, 0.4 in his ch. 6); NaN = from `slip` (-1 no-slip, +1 free-slip)
  double tangential_factor = std::numeric_limits<double>::quiet_NaN();
};

struct ShapeConfig {
  std::string type;   // box | tank | polygon | plane | mesh
  std::string fill;   // fluid | wall
  std::vector<double> min, max;  // box, tank, plane extent
  std::vector<std::array<double, 2>> vertices;  // polygon (2D)
  std::vector<double> point, normal;            // plane: a point on it and its outward normal
  double thickness = 0.0;                       // plane: 0 = wall layers
  bool open_top = true;                         // tank
  std::vector<double> velocity;                 // initial velocity
  bool slope = false;  // made from `type: slope` (vertices computed by the reader)
  std::vector<std::array<double, 2>> solid;  // slope walls: the whole wedge under the surface, kept free of fluid
  std::vector<std::array<double, 2>> surface;  // slopes: the surface line (the face) from the toe to the top
  // slope walls: the line their wall rows follow: the face and, where `back` leaves a crest, the crest and the
  // back face down to the toe's level (water that comes over the crest meets a wall, not the wedge's hollow)
  std::vector<std::array<double, 2>> outline;
  std::string motion;  // wall shapes: the name of the prescribed motion that moves them (`motions:`); empty = fixed
  std::shared_ptr<const SolidMesh> mesh;  // mesh (3D): the solid, read, transformed and checked by the reader
  int line = 0;
};

/// A prescribed rigid translation of the wall particles of the shapes that name it (a piston
/// wave maker): x = x_0 + X(t) e along the unit direction e (boundaries/motion.hpp, laws in
/// boundaries/paddle.hpp).
struct MotionConfig {
  std::string name;
  std::string law;                  // solitary | regular | stokes2 | table | irregular | focused | elevation
  std::vector<double> direction;    // e (normalised by the reader); default +x
  std::string theory = "rayleigh";  // solitary: rayleigh (implicit, Newton) | goring | rayleigh_explicit
  double height = 0.0;              // H: solitary and regular waves [m]
  double depth = 0.0;               // h0: still water depth at the paddle [m]
  double period = 0.0;              // regular, stokes2: T [s]
  double start = 0.0;               // the law's time origin: the paddle rests before it [s]
  double ramp = 0.0;                // regular, stokes2, table: start-up ramp (1 - cos)/2 over this time [s]
  std::string file;                 // table: CSV of time, displacement (as written in the case, resolved by the reader)
  std::vector<double> table_t, table_x;  // table: the samples
  double gravity = 9.81;            // |g| (set from the case's gravity)
  // irregular and focused waves (boundaries/wave_spectrum.hpp)
  std::string spectrum = "jonswap";  // jonswap | pierson_moskowitz
  double hm0 = 0.0;                 // irregular: significant height 4 sqrt(m0) [m]
  double tp = 0.0;                  // irregular, focused: peak period [s]
  double gamma = 3.3;               // jonswap: peak enhancement
  std::uint64_t seed = 1;           // irregular: the random phases' seed
  int components = 0;               // number of frequencies (0: chosen from the run's length)
  double f_min = 0.0, f_max = 0.0;  // frequency band [Hz] (0: the law's default)
  double amplitude = 0.0;           // focused: the crest amplitude at the focus [m]
  double focus_x = 0.0;             // focused: distance of the focus from the paddle's rest face [m]
  double focus_time = 0.0;          // focused: time of the focus after `start` [s]
  std::vector<double> elevation_t, elevation_eta;  // elevation: the target surface elevation at the paddle
  // regular, irregular, focused, elevation: Schäffer's (1996) second-order correction of the paddle's
  // motion (boundaries/paddle_order2.hpp) with this many evanescent modes (extrapolated from half of them)
  bool second_order = false;
  int evanescent_modes = 20;
  // the paddle's kind: a piston translates; a flap rotates about a horizontal hinge (boundaries/motion.hpp)
  std::string paddle = "piston";    // piston | flap
  std::vector<double> hinge;        // flap: a point of the hinge line [m]
  double hinge_depth = 0.0;         // flap: the hinge's depth below the still-water level, d (≤ depth) [m]
  // active absorption (Schäffer & Klopman 2000, boundaries/motion.hpp): the level measured at the
  // paddle's face, at the offset of the named water_level gauge, moving with the paddle
  bool absorb = false;
  std::string absorb_gauge;         // the water_level gauge at the face
  double absorb_offset = 0.0;       // its distance ahead of the paddle's rest face, along the motion [m]
  std::vector<double> absorb_point; // the gauge's point (z ignored)
  double drift_time = 0.0;          // the time constant of the drift correction [s] (0: the law's default)
  double absorb_start = 0.0;        // the correction acts after this time [s] (default: start + ramp, at least 1 s)
  int line = 0;
};

struct GaugeConfig {
  std::string name, type;  // water_level | pressure | velocity_profile | stress_profile | depth_profile | front | energy | flux
  std::vector<double> point, start, end;
  double x = 0.0;  // water_level: vertical line at x (and y in 3D via point)
  int points = 20;
  int axis = 0;     // front: axis along which the surge runs
  double direction = 1.0;  // front: +1 or -1
  // profiles and flux: also write NAME.mean.csv, the mean of the samples at t >= average_from
  double average_from = std::numeric_limits<double>::infinity();
  std::string field;  // scalar gauges: the transported scalar's name; paddle: the motion's name
  // runup: still-water level z, the reach from the slope line [m] (0 = 1.5 dx), the thinnest water
  // layer normal to the slope that counts as wet [m] (a lab wire's 1 mm) and the fewest fluid
  // neighbours within 2 dx a particle needs to count
  // (overtopping: `level` holds the crest's width in 3D)
  double level = 0.0, reach = 0.0, film = 0.001;
  int neighbours = 2;
  int line = 0;
  // pressure: a lab sensor. diameter > 0: the mean over its face (a segment in 2D, a disk in
  // 3D) normal to `normal`; window > 0: the mean (and standard deviation) of the samples taken
  // after every step in the last `window` seconds before each output time
  double diameter = 0.0, window = 0.0;
  std::vector<double> normal;
  // flux, scalar_flux in 3D: the section across y, [y0, y1], cut into `columns` strips, a line at
  // the middle of each (empty: the flux per metre of width at the line's y)
  std::vector<double> span;
  int columns = 0;
};

/// A velocity profile u(z) along the flow direction, z measured from the bed.
struct ProfileConfig {
  std::string type = "uniform";  // uniform | parabolic | log | table
  double u = 0.0;                // uniform: u
  double u_surface = 0.0;        // parabolic: u at the surface, u = u_s (2 ζ − ζ²), ζ = z / depth
  double u_star = 0.0, ks = 0.0; // log: u = u*/κ ln(z/ks) + 8.5 u* (Nikuradse, rough), κ = 0.41
  std::vector<double> z, values; // table: u at heights z (linear in between, constant outside)
};

/// An open boundary zone across the channel, flow along +x (Federico's in/out-flow algorithm).
struct OpenBoundaryConfig {
  std::string type;              // inflow | outflow
  double x0 = 0.0, x1 = 0.0;     // the zone along x: [x0, x1)
  double bed = 0.0;              // z of the bed (the profile's z = 0)
  double depth = 0.0;            // inflow: imposed depth (particles fill bed <= z < bed + depth);
                                 // outflow: the depth the profile is scaled with
  bool frozen = false;           // outflow: keep the velocity held on entering (true) or impose the profile
  // Kazemi's unknown-discharge inflow (averaged) and zero-gradient outflow (extrapolated): the
  // particles take the Shepard average of the fluid's velocity and density at a node 0.5 dx
  // inside the fluid at their height, before every rates pass
  std::string velocity = "imposed";  // inflow: imposed | averaged; outflow: imposed | frozen | extrapolated
  std::string pressure = "frozen";   // outflow: frozen | extrapolated | hydrostatic (local depth) | imposed (of `depth`) | inlet
  bool initial_profile = false;  // inflow: also give the fluid downstream the profile at t = 0
  // inflow `averaged`: distance of the velocity's averaging node downstream of the inlet line
  // (0 = Kazemi's 0.5 dx; a distance well inside the channel recycles the developed profile);
  // the density is always averaged 0.5 dx inside
  double average_at = 0.0;
  ProfileConfig profile;
  int line = 0;
};

/// Drag closure of a porous region (per unit mass, on the intrinsic velocity u; K = a + b |u|,
/// drag = -K u). See physics/porous.hpp for the formulas.
struct PorousClosureConfig {
  std::string type = "ergun";  // ergun | tsurudome | van_gent | roughness
  double c1 = 150.0, c2 = 1.75;  // ergun, tsurudome: linear and quadratic constants; van_gent: alpha, beta
  double added_mass = 0.0;       // van_gent: gamma of the added-mass factor 1 + gamma (1 - phi)/phi
  double kc = 0.0;               // van_gent: Keulegan-Carpenter number of the 1 + 7.5/KC factor; 0 = steady (no term)
  double cd = 0.9, factor = 1.0; // roughness (Kazemi eq 6.2): -factor cd (1 - phi) u|u| / d_s
};

/// A porous region: a shape (box, polygon) of porosity phi0 and grain diameter, or a prescribed
/// porosity profile phi(z) or phi(x, z) (Kazemi's Situation #2).
struct PorousRegionConfig {
  std::string shape = "box";  // box | polygon | profile | mesh
  std::vector<double> min, max;
  std::vector<std::array<double, 2>> vertices;
  std::vector<std::array<double, 2>> surface;  // shape slope: its surface line from the toe (a band follows it)
  std::shared_ptr<const SolidMesh> mesh;  // mesh (3D): the solid, read and checked by the reader
  double porosity = 1.0;      // phi0 (shapes)
  double diameter = 0.0;      // grain diameter d_s [m]
  double layer = 0.0;         // field smoothed: thickness of the transition layer [m]; 0 = the diameter
  PorousClosureConfig closure;
  // Kazemi eq 6.3/6.9: a second closure above a level (the roughness layer above the trough z_t)
  // and downstream of a station (X2 of the porous inflow's transition); the first one elsewhere
  bool has_upper = false;
  double upper_z = 0.0, upper_x = -1e300;
  PorousClosureConfig upper;
  std::vector<double> x, z;                // profile: stations (x optional) and heights
  std::vector<std::vector<double>> phi;    // profile: phi[ix][iz] (one row without x)
  int line = 0;
};

struct PorousConfig {
  // how shapes become a porosity field: smoothed (Kazemi's Situation #1: the indicator convolved
  // over a layer `layer` thick), particles (Tsurudome eq 4.2.1: kernel sum of porous particles),
  // sharp (the indicator itself)
  std::string field = "smoothed";
  bool literal_normalisation = false;  // particles: Tsurudome's rho_p / rho_w as printed (gives 1-(1-phi)phi inside)
  double mesh_ratio = 1.2;             // smoothed: background mesh spacing = h_Omega / mesh_ratio (Kazemi: 1.2)
  // initial state: iterations of relax_porous_band (the interface band's points shifted until
  // the volumes m/(φρ0) tile space); 0 = the plain lattice fill
  int relax_iterations = 0;
  std::vector<PorousRegionConfig> regions;
  // boxes whose initial fluid is placed at the spacing of a given porosity (e.g. Kazemi ch. 6:
  // the bed below the crest and the porous inflow's region), after the shape regions
  struct Fill { std::vector<double> min, max; double porosity = 1.0; };
  std::vector<Fill> fill;
  int line = 0;
  bool on() const { return !regions.empty(); }
};

/// A region of space: box (min, max), circle / sphere (center, radius) or polygon (2D).
class DistanceGrid;  // core/solid_mesh.hpp

struct RegionConfig {
  std::string type = "box";  // box | circle (3D: sphere) | polygon (2D) | cylinder (3D) | mesh (3D) | band (2D)
  std::vector<double> min, max, center;
  double radius = 0.0;
  // mesh: the solid's signed distance (negative inside); inside the solid or within `margin` of its surface.
  // cylinder: a vertical axis through center (x, y), the radius, between z_min and z_max (below)
  std::shared_ptr<const DistanceGrid> grid;
  double margin = 0.0;
  std::vector<std::array<double, 2>> vertices;  // polygon; band: the slope's surface line from its toe
  double above = 0.0, below = 0.0;              // band: its extent normal to the line, above and below it
  double z_min = 0.0, z_max = 0.0;              // band, cylinder: its elevations
  // band, `follow: waterline`: the elevations [z_w - waterline_below, z_w + waterline_above] about the
  // waterline z_w on the line, within [z_min, z_max]; the run sets the window (win_lo, win_hi) each
  // step (physics/resolution.hpp, set_waterline_windows); unset, the band is the fixed one
  bool follow_waterline = false;
  double waterline_below = 0.0, waterline_above = 0.0;
  double win_lo = -1e300, win_hi = 1e300;
  /// Is x (D coordinates) inside?
  bool contains(const double* x, int dim) const;
};

/// How a transported scalar starts: later entries overwrite earlier ones where they apply.
struct ScalarInitConfig {
  std::string type = "uniform";  // uniform | region | gaussian | expression
  double value = 0.0;            // uniform, region: the value; gaussian: the peak
  RegionConfig region;           // region
  std::vector<double> center;    // gaussian: C = value exp(-|x - center|² / (2 sigma²)) over `axes`
  double sigma = 0.0;
  std::vector<int> axes;         // gaussian: the axes the distance is measured along (all when empty)
  std::string expression;        // expression of x, y, z (muparser syntax: exp, sin, ^, ...)
  int line = 0;
};

/// A prescribed concentration or flux on the wall particles inside a region (a source).
struct ScalarSourceConfig {
  RegionConfig region;
  bool has_value = false;
  double value = 0.0;  // Dirichlet: the wall particles hold C = value and exchange with the fluid
  double flux = 0.0;   // Neumann: kg/(m² s) out of the region's wall surface into the fluid
  int line = 0;
};

/// One transported scalar (concentration, temperature, ...): DC/Dt = (1/ρ)∇·(ρD∇C) − R (C − C_eq).
struct ScalarConfig {
  std::string name;
  double diffusivity = 0.0;         // molecular D [m²/s]
  double schmidt_turbulent = 0.0;   // > 0: D += ν_t / Sc_t from the turbulence model
  double reaction_rate = 0.0;       // first-order rate R [1/s] towards `equilibrium`
  double equilibrium = 0.0;
  std::vector<ScalarInitConfig> initial;
  bool has_inflow = false;          // inflow particles carry `inflow` (between inflow_z[0] and inflow_z[1])
  double inflow = 0.0;
  std::array<double, 2> inflow_z{-1e300, 1e300};
  std::vector<ScalarSourceConfig> sources;
  int line = 0;
};

enum class DiffusionOperator { Consistent, Federico, ZhuFox, Tartakovsky, Monaghan };
enum class ScalarAdvection { Conservative, None, ThesisLiteral };

struct TransportConfig {
  DiffusionOperator op = DiffusionOperator::Consistent;
  ScalarAdvection advection = ScalarAdvection::Conservative;
  // η²/h² of F_ab = r·∇W/(r² + η²) in the diffusion sums: only guards coincident particles;
  // the thesis's 0.01 weakens the nearest-neighbour terms by ~1-4 % (lattice test in
  // validation/scalar_diffusion), so the default is 1e-4
  double eta2 = 1e-4;
  std::vector<ScalarConfig> scalars;
  int line = 0;
  bool on() const { return !scalars.empty(); }
};

/// A second fluid phase (a pollutant or air) occupying `region` at the start; its particles
/// carry its own reference density and equation of state (Federico ch. 8, 9).
struct PhaseConfig {
  std::string name;
  double density = 1000.0;
  double gamma = 7.0;
  double sound_speed = 0.0;  // 0 = equal B with the water: c0 sqrt(γ ρ_w / (γ_w ρ))
  RegionConfig region;
  int line = 0;
};

struct MultiphaseConfig {
  std::vector<PhaseConfig> phases;
  // Grenier et al. (2009) (Federico's System 4): per-phase Shepard density and the Γ-normalised
  // pressure gradient, with the interface term chi; off: the Colagrossi-Landrini form of the scheme
  bool grenier = false;
  double chi = 0.0;          // interface repulsion coefficient (Federico: 0.08 for air)
  int line = 0;
  bool on() const { return !phases.empty(); }
};

/// A refined region (variable resolution, docs/numerics.md §14): the fluid that starts inside it
/// is split to level `level` (spacing dx / 2^level, h / 2^level, mass / 2^(D level)).
struct ResolutionRegionConfig {
  RegionConfig region;
  int level = 1;
  int line = 0;
};
/// The cell list's layout with resolution levels (`resolution.cells`, core/system.hpp): level 0's cells (each cell's
/// 3^D stencil), the finest pairs' cells (each cell's stencil narrowed to its pairs), or one grid of cells per level
/// (core/cell_grids.hpp).
enum class CellLayout { Level0, Finest, Levels };
struct ResolutionConfig {
  std::vector<ResolutionRegionConfig> regions;
  int relax_iterations = 300;  // the level interface's relaxation at set-up (physics/resolution.hpp)
  int settle_iterations = 10;  // the shifts of each split's children (physics/resolution.hpp adapt_levels)
  bool multirate = false;      // the finest level sub-cycled at half the others' step (schemes/multirate.hpp)
  CellLayout cells = CellLayout::Levels;  // `cells`: the cell list's layout (core/system.hpp)
  int multirate_line = 0;
  int line = 0;
  bool on() const { return !regions.empty(); }
  int max_level() const {
    int m = 0;
    for (const auto& r : regions) m = r.level > m ? r.level : m;
    return m;
  }
};

struct Case {
  std::string file;  // where it came from (for messages)
  std::string name = "case";
  int dimension = 2;
  double dx = 0.0;
  double h_over_dx = 0.0;  // 0 = kernel default
  KernelType kernel = KernelType::WendlandC2;
  std::vector<double> gravity;
  std::vector<double> domain_min, domain_max;  // empty = bounding box of the geometry
  std::vector<int> periodic;                   // axes
  FluidConfig fluid;
  SchemeConfig scheme;  // type, and the weakly-compressible scheme's options
  IsphConfig isph;      // the projection scheme's options (scheme.type: isph)
  std::vector<std::string> warnings;  // input that is accepted but ignored (printed; summary.json)
  WallConfig walls;
  std::vector<ShapeConfig> shapes;
  std::vector<MotionConfig> motions;  // prescribed wall motions (wave makers), by name
  int geometry_line = 0;  // line of the 'geometry' key (for messages about the shapes as a whole)
  double t_end = 0.0, output_interval = 0.0;
  long snapshot_every = 1;  // a snapshot at every N-th output (time.snapshot_interval = N output_interval); gauges at every one
  std::vector<GaugeConfig> gauges;
  Node forces;  // list of registered force terms, each {type: NAME, ...} (read when the run is set up)
  std::vector<OpenBoundaryConfig> open_boundaries;
  TurbulenceConfig turbulence;
  PorousConfig porous;
  TransportConfig transport;
  MultiphaseConfig multiphase;
  ResolutionConfig resolution;  // refined regions (`resolution:`; none: one level)
  std::string fingerprint;  // canonical text of the document after --set, time.end left out (restart check)

  double h() const { return h_over_dx * dx; }
};

}  // namespace sph
