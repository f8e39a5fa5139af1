// An independent build of the caterpillar in MuJoCo (Debian's libmujoco 2.2.2), for the
// transfer benchmark and the gap finder's foreign cases: NOT the ODE model gaitforge
// evolves and calibrates on, and not bench/diagnosis/rig2d.py either. Its numbers are the
// fact sheet's (../shared/robots/caterpillar.md), written here on purpose: an independent
// build must not read the model's descriptor, or its errors would be shared.
//
// What differs from the ODE model, on purpose:
//   - generalised coordinates: a kinematic chain rooted at the rear lump (planar root: x, z,
//     pitch), each link an axial slide, a shear slide (20x the axial spring) and a bending
//     hinge at the link's midpoint, instead of maximal coordinates and constraint rows;
//   - soft contact: MuJoCo's convex, regularised contact with Coulomb friction mu = 2 on an
//     elliptic cone (the paper's no-slip approximated), instead of ODE's LCP without slip;
//   - pistons: spatial tendons between the attachment sites, driven by a motor; their stroke
//     stops are MuJoCo's soft tendon limits;
//   - bending damping: critical for the reduced inertia about the hinge at the link's
//     midpoint (the lumps' own inertia plus m d^2), not about the lumps' centres;
//   - integration: MuJoCo's Euler (implicit in joint damping) at 0.25 ms.
// Effects in forms of its own: a hose pulling the rear lump straight back, growing with
// travel; linear drag on every lump; a first-order lag on the pistons' force; a slope; a
// weaker air supply (the pistons' force times force_scale). And its structure varied, for nulls
// of another build: ground_mu (default 2) and contact_time_s (MuJoCo's solref time constant,
// default 0.002 s).
//
//   gaitforge-bench-caterpillar-mujoco [--settle N] [--cycles N] [--record FILE --rate HZ]
//
// Reads one run per line on stdin: the 13 genes of the paper's gait (a_T1..a_B3, d_T1..d_B3,
// T), then any of hose_n=, hose_n_per_m= (with hose_anchor_x_m=, the markers' mean x from
// which the hose's travel counts; default: where they rest), drag_n_s_per_m=, actuator_lag_s=, slope_rad=,
// force_scale=, ground_mu=, contact_time_s=. Prints one line per run: the forward travel per cycle (m) of the markers'
// mean x over --cycles periods after --settle, or "nan REASON" for a run that diverged. --record writes the
// first run's markers (docs/recording-format.md) from the end of the settle cycles.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// The fact sheet's numbers.
constexpr double kMass = 0.030, kHalfX = 0.015, kHalfY = 0.020, kHalfZ = 0.0125, kSpacing = 0.032;
constexpr double kFlexureK = 1040, kFlexureKb = 0.12, kSegmentK = 446, kSegmentKb = 0.07;
constexpr double kForce = 8.8, kReturnK = 63, kMinLength = 0.051, kMaxLength = 0.062;
constexpr double kAttachX = 0.0095, kTopZ = 0.0125, kBottomZ = -0.0080;
// This build's own choices.
constexpr double kShearFactor = 20, kMu = 2.0, kContactTime = 0.002, kStep = 0.00025;

double Critical(double k, double m) { return 2 * std::sqrt(k * m); }

std::string Num(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

// Joints of lump i (1-based) relative to lump i - 1: axial, shear, bending at the midpoint.
std::string LinkJoints(int i) {
  const bool flexure = (i - 1) % 2 == 1;  // links (1,2) (3,4) (5,6)
  const double k = flexure ? kFlexureK : kSegmentK, kb = flexure ? kFlexureKb : kSegmentKb;
  const double m_red = kMass / 2;
  const double inertia = kMass * (4 * kHalfX * kHalfX + 4 * kHalfZ * kHalfZ) / 12;
  const double i_red = (inertia + kMass * (kSpacing / 2) * (kSpacing / 2)) / 2;
  const std::string mid = "pos=\"" + Num(-kSpacing / 2) + " 0 0\"";
  std::ostringstream s;
  s << "<joint name=\"axial" << i << "\" type=\"slide\" axis=\"1 0 0\" stiffness=\"" << Num(k)
    << "\" damping=\"" << Num(Critical(k, m_red)) << "\"/>\n"
    << "<joint name=\"shear" << i << "\" type=\"slide\" axis=\"0 0 1\" stiffness=\"" << Num(kShearFactor * k)
    << "\" damping=\"" << Num(Critical(kShearFactor * k, m_red)) << "\"/>\n"
    << "<joint name=\"bend" << i << "\" type=\"hinge\" axis=\"0 1 0\" " << mid << " stiffness=\""
    << Num(kb) << "\" damping=\"" << Num(Critical(kb, i_red)) << "\"/>\n";
  return s.str();
}

// Lump i's geometry, marker and actuator sites; pistons j span lumps (2j-1, 2j).
std::string LumpBody(int i) {
  std::ostringstream s;
  s << "<geom type=\"box\" size=\"" << kHalfX << " " << kHalfY << " " << kHalfZ << "\" mass=\"" << kMass
    << "\"/>\n<site name=\"m" << i << "\" pos=\"0 0 " << kHalfZ << "\"/>\n";
  const int j = (i + 1) / 2;
  const double x = i % 2 == 1 ? -kAttachX : kAttachX;
  s << "<site name=\"T" << j << "_" << i << "\" pos=\"" << x << " 0 " << kTopZ << "\"/>\n"
    << "<site name=\"B" << j << "_" << i << "\" pos=\"" << x << " 0 " << kBottomZ << "\"/>\n";
  return s.str();
}

// The build's own structure, which a run may vary (a null of another build): the ground's
// friction and the contact's time constant.
std::string Mjcf(double slope_rad, double mu, double contact_time_s) {
  std::ostringstream s;
  s << "<mujoco model=\"caterpillar-independent\">\n<option timestep=\"" << kStep
    << "\" integrator=\"Euler\" cone=\"elliptic\" gravity=\"" << Num(-9.81 * std::sin(slope_rad)) << " 0 "
    << Num(-9.81 * std::cos(slope_rad)) << "\"/>\n"
    << "<default><geom friction=\"" << Num(mu) << " 0.005 0.0001\" solref=\"" << Num(contact_time_s)
    << " 1\" condim=\"3\"/>"
    << "<tendon solreflimit=\"0.002 1\"/></default>\n<worldbody>\n"
    << "<geom type=\"plane\" size=\"5 1 0.1\"/>\n<body name=\"l1\" pos=\"0 0 " << kHalfZ << "\">\n"
    << "<joint name=\"root_x\" type=\"slide\" axis=\"1 0 0\"/><joint name=\"root_z\" type=\"slide\" "
       "axis=\"0 0 1\"/><joint name=\"root_pitch\" type=\"hinge\" axis=\"0 1 0\"/>\n"
    << LumpBody(1);
  for (int i = 2; i <= 6; ++i) s << "<body name=\"l" << i << "\" pos=\"" << kSpacing << " 0 0\">\n" << LinkJoints(i) << LumpBody(i);
  for (int i = 1; i <= 6; ++i) s << "</body>\n";
  s << "</worldbody>\n<tendon>\n";
  for (const char* side : {"T", "B"})
    for (int j = 1; j <= 3; ++j)
      s << "<spatial name=\"" << side << j << "\" limited=\"true\" range=\"" << kMinLength << " " << kMaxLength
        << "\"><site site=\"" << side << j << "_" << 2 * j - 1 << "\"/><site site=\"" << side << j << "_" << 2 * j
        << "\"/></spatial>\n";
  s << "</tendon>\n<actuator>\n";
  for (const char* side : {"T", "B"})
    for (int j = 1; j <= 3; ++j) s << "<motor tendon=\"" << side << j << "\" gear=\"1\"/>\n";
  s << "</actuator>\n</mujoco>\n";
  return s.str();
}

[[noreturn]] void Throw(const char* msg) { throw std::runtime_error(msg); }
void Warn(const char*) {}

mjModel* Load(const std::string& xml) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "cat.xml", static_cast<int>(xml.size()));
  std::memcpy(vfs.filedata[mj_findFileVFS(&vfs, "cat.xml")], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* m = mj_loadXML("cat.xml", &vfs, error, sizeof error);
  mj_deleteVFS(&vfs);
  if (!m) throw std::runtime_error(std::string("MuJoCo refused the model: ") + error);
  return m;
}

struct Run {
  std::vector<double> genes;              // 13
  std::map<std::string, double> effects;  // name -> value
  double effect(const char* name, double otherwise = 0.0) const {
    auto it = effects.find(name);
    return it == effects.end() ? otherwise : it->second;
  }
};

bool On(const std::vector<double>& g, int j, double t) {
  const double period = g[12], phase = std::fmod(t, period) / period;
  const double a = std::fmod(g[j], 1.0), d = std::fmod(g[6 + j], 1.0);
  return a <= d ? (phase >= a && phase < d) : (phase >= a || phase < d);
}

// The markers' mean x and, with `row`, every marker's x, y, z.
double MarkerMeanX(const mjModel* m, const mjData* d, std::vector<double>* row) {
  double sum = 0;
  for (int i = 1; i <= 6; ++i) {
    const int id = mj_name2id(m, mjOBJ_SITE, ("m" + std::to_string(i)).c_str());
    sum += d->site_xpos[3 * id];
    if (row) row->insert(row->end(), d->site_xpos + 3 * id, d->site_xpos + 3 * id + 3);
  }
  return sum / 6;
}

// Forces of one step: the gait's pistons (lagged), their return springs, the effects.
void Drive(const mjModel* m, mjData* d, const Run& run, std::vector<double>& lagged, double x0) {
  const double lag = run.effect("actuator_lag_s");
  const double keep = lag > 0 ? std::exp(-kStep / lag) : 0.0;
  for (int j = 0; j < 6; ++j) {
    const double target = On(run.genes, j, d->time) ? kForce * run.effect("force_scale", 1.0) : 0.0;
    lagged[j] = keep * lagged[j] + (1 - keep) * target;
    d->ctrl[j] = lagged[j] - kReturnK * (d->ten_length[j] - kMinLength);
  }
  std::fill(d->xfrc_applied, d->xfrc_applied + 6 * m->nbody, 0.0);
  const double travel = std::max(0.0, MarkerMeanX(m, d, nullptr) - x0);
  d->xfrc_applied[6 * 1] -= run.effect("hose_n") + run.effect("hose_n_per_m") * travel;
  const double drag = run.effect("drag_n_s_per_m") / 6;
  for (int b = 1; b <= 6; ++b) {
    mjtNum vel[6];
    mj_objectVelocity(m, d, mjOBJ_BODY, b, vel, 0);
    d->xfrc_applied[6 * b] -= drag * vel[3];
    d->xfrc_applied[6 * b + 2] -= drag * vel[5];
  }
}

std::string Diverged(const mjData* d, const mjModel* m) {
  if (d->warning[mjWARN_BADQACC].number > 0) return "MuJoCo: bad acceleration";
  for (int i = 0; i < m->nv; ++i)
    if (!std::isfinite(d->qvel[i]) || std::fabs(d->qvel[i]) > 1e4) return "a velocity above 1e4";
  return "";
}

// One row of the recording at `time`; moves `time` on by one sample.
void Sample(const mjModel* m, const mjData* d, std::ostream* record, double& time, double rate) {
  std::vector<double> row;
  MarkerMeanX(m, d, &row);
  *record << Num(time);
  for (double v : row) *record << "," << Num(v);
  *record << "\n";
  time += 1.0 / rate;
}

// Travel per cycle of one run; writes its markers to `record` at `rate` Hz when given.
std::string Simulate(const Run& run, int settle, int cycles, std::ostream* record, double rate) {
  mjModel* m = Load(Mjcf(run.effect("slope_rad"), run.effect("ground_mu", kMu),
                         run.effect("contact_time_s", kContactTime)));
  mjData* d = mj_makeData(m);
  // The markers' positions at rest: mj_makeData leaves site_xpos at zero until kinematics
  // run (before this, the rest position read 0 and a recording from rest began with zeros).
  // Kinematics only: the dynamics and the solver's warm start are untouched.
  mj_kinematics(m, d);
  std::vector<double> lagged(6, 0.0);
  const double period = run.genes[12], start = settle * period, end = (settle + cycles) * period;
  // Where a growing hose counts its travel from: the rest position, or hose_anchor_x_m (the
  // suite's growing-hose cases of session 21 and 40 were recorded with it at 0, the bug above).
  const double x_rest = run.effects.count("hose_anchor_x_m") ? run.effect("hose_anchor_x_m")
                                                             : MarkerMeanX(m, d, nullptr);
  double x_start = NAN, next_sample = start;
  std::string reason;
  if (record) {
    *record << "t";
    for (int i = 1; i <= 6; ++i) *record << ",m" << i << ".x,m" << i << ".y,m" << i << ".z";
    *record << "\n";
  }
  while (reason.empty() && d->time < end - kStep / 2) {
    if (std::isnan(x_start) && d->time >= start - kStep / 2) x_start = MarkerMeanX(m, d, nullptr);
    if (record && d->time >= next_sample - kStep / 2) Sample(m, d, record, next_sample, rate);
    mj_step1(m, d);
    Drive(m, d, run, lagged, x_rest);
    mj_step2(m, d);
    reason = Diverged(d, m);
  }
  if (record && reason.empty() && next_sample <= end + kStep / 2) Sample(m, d, record, next_sample, rate);
  const double x_end = MarkerMeanX(m, d, nullptr);
  mj_deleteData(d);
  mj_deleteModel(m);
  if (!reason.empty()) return "nan " + reason;
  return Num((x_end - x_start) / cycles);
}

Run Parse(const std::string& line, int number) {
  std::istringstream in(line);
  Run run;
  std::string token;
  while (in >> token) {
    const auto eq = token.find('=');
    if (eq == std::string::npos) {
      run.genes.push_back(std::stod(token));
    } else {
      run.effects[token.substr(0, eq)] = std::stod(token.substr(eq + 1));
    }
  }
  static const std::vector<std::string> known = {"hose_n",    "hose_n_per_m", "hose_anchor_x_m",
                                                 "drag_n_s_per_m", "actuator_lag_s", "slope_rad",
                                                 "force_scale", "ground_mu", "contact_time_s"};
  const std::string where = "stdin:" + std::to_string(number) + ": ";
  for (const auto& [name, value] : run.effects)
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      throw std::invalid_argument(where + "unknown effect '" + name + "' (known: " + list + ")");
    }
  const double mu = run.effect("ground_mu", kMu), contact = run.effect("contact_time_s", kContactTime);
  if (!(mu > 0 && mu <= 10)) throw std::invalid_argument(where + "ground_mu must be in (0, 10]");
  if (!(contact >= 2 * kStep && contact <= 0.05))
    throw std::invalid_argument(where + "contact_time_s must be in [0.0005, 0.05] (at least two steps)");
  if (run.genes.size() != 13 || !(run.genes[12] >= 0.2 && run.genes[12] <= 2.0))
    throw std::invalid_argument(where + "a run is 13 genes (period T in [0.2, 2] s last), then effects");
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  int settle = 2, cycles = 5;
  double rate = 100;
  std::string record;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::cout << "usage: gaitforge-bench-caterpillar-mujoco [--settle N] [--cycles N] [--record FILE] [--rate HZ]\n"
                   "stdin: per line 13 gait genes, then effects name=value; stdout: travel per cycle (m)\n";
      return 0;
    }
    if (i + 1 >= argc) { std::cerr << a << ": needs a value\n"; return 2; }
    const std::string v = argv[++i];
    if (a == "--settle") settle = std::stoi(v);
    else if (a == "--cycles") cycles = std::stoi(v);
    else if (a == "--record") record = v;
    else if (a == "--rate") rate = std::stod(v);
    else { std::cerr << "unknown option " << a << " (see --help)\n"; return 2; }
  }
  mju_user_error = Throw;
  mju_user_warning = Warn;
  try {
    std::string line;
    for (int n = 1; std::getline(std::cin, line); ++n) {
      if (line.find_first_not_of(" \t") == std::string::npos) continue;
      const Run run = Parse(line, n);
      std::ofstream out;
      if (!record.empty()) out.open(record);
      std::cout << Simulate(run, settle, cycles, record.empty() ? nullptr : &out, rate) << std::endl;
      record.clear();
    }
  } catch (const std::exception& e) {
    std::cerr << "gaitforge-bench-caterpillar-mujoco: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
