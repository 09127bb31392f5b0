// Siconos's D1MinusLinearOSI (Schindler & Acary's time-discontinuous
// Galerkin scheme) with TimeSteppingD1Minus on the small systems of
// tests/siconos/moreau_jean.py: the numbers that
// crates/schemes/tests/it/siconos.rs compares `d1-minus-linear(e)` (the
// acceleration-level rows) and `d1-minus-linear-velocity(e)` (the
// velocity-level rows) with, step by step. Writes data/siconos/d1-minus-linear.csv (every digit, %.17g).
//
// Siconos 4.4.0 (Debian bookworm) ships libsiconos_kernel.so.7 but its
// Python bindings lack D1MinusLinearOSI and its -dev packages do not
// install next to python3-siconos; the headers are unpacked by hand:
//
//   mkdir -p /tmp/d1sic/debs && cd /tmp/d1sic/debs
//   apt-get download libsiconos-kernel-dev libsiconos-numerics-dev libboost1.74-dev
//   for d in *.deb; do dpkg -x $d /tmp/d1sic/root; done
//   I=/tmp/d1sic/root/usr/include; L=/usr/lib/x86_64-linux-gnu
//   g++ -O1 -std=c++17 -I$I -I$I/siconos -I$I/siconos/kernel -I$I/siconos/numerics \
//     tests/siconos/d1_minus_linear.cpp -o /tmp/d1sic/d1 \
//     $L/libsiconos_kernel.so.7 $L/libsiconos_numerics.so.7
//   /tmp/d1sic/d1 > data/siconos/d1-minus-linear.csv      (from the repository's root)
//
// The systems (as moreau_jean.py; change all together): M q'' + C q' + K q = F,
// three dofs, M = [[2,1,0],[1,4,1],[0,1,2]]/6, K = 30 [[1,-1,0],[-1,2,-1],[0,-1,1]],
// C = 0.1 M + 0.05 K or none, a steady load F, contacts q_0 >= 0 (e_0) and,
// with two contacts, q_2 <= 0.08 (e_2). Siconos: LagrangianLinearTIDS, one
// LagrangianLinearTIR per contact (y = H q + b >= 0), NewtonImpactNSL(e),
// D1MinusLinearOSI(type) (halfexplicit_acceleration_level, Siconos's default,
// or halfexplicit_velocity_level), TimeSteppingD1Minus with two LCP()
// (Lemke): the impact problem (velocity level) and the force problem.
// Columns: case, level (acceleration or velocity), step, t, q0..q2, v0..v2, p0, p2 (the
// impulses, lambda(1), of the contacts at the step's end; p2 is 0 with one
// contact), f0, f2 (lambda(2), the last contact force the step computed).
#include <SiconosKernel.hpp>
#include <cstdio>
#include <string>
#include <vector>

struct Contact { int dof; bool lo; double bound; double e; };
struct Case { const char* name; std::vector<Contact> contacts; bool damped; double load[3]; };

static void run(const Case& c, unsigned int variant, const char* level)
{
  const double h = 0.01; const int steps = 300;
  const double m[3][3] = {{2, 1, 0}, {1, 4, 1}, {0, 1, 2}};
  const double k[3][3] = {{1, -1, 0}, {-1, 2, -1}, {0, -1, 1}};
  SP::SimpleMatrix M(new SimpleMatrix(3, 3)), K(new SimpleMatrix(3, 3)), C(new SimpleMatrix(3, 3));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      (*M)(i, j) = m[i][j] / 6.0;
      (*K)(i, j) = k[i][j] * 30.0;
      (*C)(i, j) = c.damped ? 0.1 * (m[i][j] / 6.0) + 0.05 * (k[i][j] * 30.0) : 0.0;
    }
  SP::SiconosVector q0(new SiconosVector(3)), v0(new SiconosVector(3)), F(new SiconosVector(3));
  const double qi[3] = {0.05, 0.0, -0.02}, vi[3] = {-1.0, 0.3, 0.8};
  for (int i = 0; i < 3; ++i) { (*q0)(i) = qi[i]; (*v0)(i) = vi[i]; (*F)(i) = c.load[i]; }
  SP::LagrangianLinearTIDS ds(new LagrangianLinearTIDS(q0, v0, M, K, C));
  ds->setFExtPtr(F);
  SP::NonSmoothDynamicalSystem nsds(new NonSmoothDynamicalSystem(0.0, h * steps));
  nsds->insertDynamicalSystem(ds);
  std::vector<SP::Interaction> inters;
  for (const Contact& ct : c.contacts) {
    SP::SimpleMatrix H(new SimpleMatrix(1, 3));
    H->zero();
    (*H)(0, ct.dof) = ct.lo ? 1.0 : -1.0;
    SP::SiconosVector b(new SiconosVector(1));
    (*b)(0) = ct.lo ? -ct.bound : ct.bound;
    SP::Interaction inter(new Interaction(SP::NonSmoothLaw(new NewtonImpactNSL(ct.e)), SP::Relation(new LagrangianLinearTIR(H, b))));
    nsds->link(inter, ds);
    inters.push_back(inter);
  }
  SP::TimeDiscretisation td(new TimeDiscretisation(0.0, h));
  SP::D1MinusLinearOSI osi(new D1MinusLinearOSI(variant));
  SP::TimeSteppingD1Minus sim(new TimeSteppingD1Minus(nsds, td, 2));
  sim->associate(osi, ds);
  sim->insertNonSmoothProblem(SP::OneStepNSProblem(new LCP()), SICONOS_OSNSP_TS_VELOCITY);
  sim->insertNonSmoothProblem(SP::OneStepNSProblem(new LCP()), SICONOS_OSNSP_TS_VELOCITY + 1);
  auto row = [&](int n, double t) {
    double p[2] = {0, 0}, f[2] = {0, 0};
    for (size_t j = 0; j < inters.size(); ++j) {
      p[j] = (*inters[j]->lambda(1))(0);
      f[j] = (*inters[j]->lambda(2))(0);
    }
    const SiconosVector& q = *ds->q(); const SiconosVector& v = *ds->velocity();
    std::printf("%s,%s,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", c.name, level, n, t,
                q(0), q(1), q(2), v(0), v(1), v(2), p[0], p[1], f[0], f[1]);
  };
  std::printf("%s,%s,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", c.name, level, 0, 0.0,
              qi[0], qi[1], qi[2], vi[0], vi[1], vi[2], 0.0, 0.0, 0.0, 0.0);
  int n = 0;
  while (sim->hasNextEvent() && n < steps) {
    sim->advanceToEvent();
    ++n;
    row(n, sim->nextTime());
    sim->processEvents();
  }
}

int main()
{
  const double lo = 0.0, hi = 0.08;
  std::vector<Case> cases = {
    {"one-contact", {{0, true, lo, 0.5}}, false, {-2.0, -0.5, -0.5}},
    {"two-contacts", {{0, true, lo, 0.5}, {2, false, hi, 0.8}}, false, {-2.0, 0.1, 1.5}},
    {"two-contacts-damped", {{0, true, lo, 0.0}, {2, false, hi, 0.8}}, true, {-2.0, 0.1, 1.5}},
  };
  std::printf("case,level,step,t,q0,q1,q2,v0,v1,v2,p0,p2,f0,f2\n");
  for (const Case& c : cases) run(c, D1MinusLinearOSI::halfexplicit_acceleration_level, "acceleration");
  for (const Case& c : cases) run(c, D1MinusLinearOSI::halfexplicit_velocity_level, "velocity");
  return 0;
}
