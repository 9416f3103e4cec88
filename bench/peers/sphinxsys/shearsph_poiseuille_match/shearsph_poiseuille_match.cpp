/**
 * @file  shearsph_poiseuille_match.cpp
 * @brief SPHinXsys's stock 2D Poiseuille case (tests/2d_examples/
 *        test_2d_poiseuille_flow, commit 9f33297), parameterised to match a
 *        `shearsph bench --sphinxsys-match` scene and instrumented for the
 *        comparison in shearsph's bench/peers/.
 *
 * What is kept from the stock case, unchanged: Wendland C2 with h = 1.3 dx
 * (SPHinXsys's default adaptation), particles on a square lattice
 * (ParticleGenerator<BaseParticles, Lattice>), walls of 4 layers above and
 * below, periodic along x by the cell-linked list, dual time stepping
 * (advection steps: density summation, kernel-gradient correction, viscous
 * force, transport velocity correction; acoustic substeps: Riemann pressure
 * relaxation, density relaxation), the advection and acoustic CFL numbers,
 * the neighbour configuration rebuilt after every advection step and particle
 * sorting every 100 advection steps.
 *
 * What is changed: the parameters come from the command line; the run starts
 * from rest, as the stock case does, and ends at an end time given as
 * tau = t nu / B^2 (the last advection step is shortened to end there, to
 * within the acoustic substep it may overrun by, as the stock loop does); no
 * output files, no regression test, no screen output in the loop. Only the
 * time-step loop is timed (std::chrono::steady_clock), not the set-up.
 *
 * Options (all optional; defaults are the stock case's values):
 *   --layers N      fluid rows in the half-width B (stock: 10, dx = 1/20)
 *   --re R          U B / nu, U the steady centre-line speed (stock: 7.5)
 *   --c0-factor F   c0 = F U (stock: 10)
 *   --tau T         end time t nu / B^2 (stock: 40, t = 100)
 *   --columns C     channel length in dx (stock: 120, DL = 6)
 *   --threads K     TBB threads (default: all cores)
 *
 * The last line printed is one JSON object: counts, steps, wall time, the
 * time reached and the profile by row (the fluid's mean x velocity per row
 * of height dx, rows by floor(y / dx)), which bench/peers/peer_metric.py
 * turns into the L_inf error against the start-up series.
 */
#include "sphinxsys.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using namespace SPH;

namespace
{
struct Options
{
    int layers = 10;
    Real re = 7.5;
    Real c0_factor = 10.0;
    Real tau = 40.0;
    int columns = 120;
    int threads = static_cast<int>(std::thread::hardware_concurrency());
};

[[noreturn]] void usage_error(const std::string &what)
{
    std::cerr << "shearsph_poiseuille_match: " << what << "\n"
              << "usage: shearsph_poiseuille_match [--layers N] [--re R] [--c0-factor F] "
                 "[--tau T] [--columns C] [--threads K]\n";
    std::exit(2);
}

Real positive_number(const char *flag, const char *text)
{
    char *end = nullptr;
    Real v = std::strtod(text, &end);
    if (end == text || *end != '\0' || !(v > 0.0) || !std::isfinite(v))
        usage_error(std::string(flag) + " " + text + ": expected a positive number");
    return v;
}

int positive_int(const char *flag, const char *text, int least)
{
    char *end = nullptr;
    long v = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || v < least || v > 100000)
        usage_error(std::string(flag) + " " + text + ": expected a whole number >= " + std::to_string(least));
    return static_cast<int>(v);
}

Options parse(int ac, char *av[])
{
    Options o;
    for (int i = 1; i < ac; i += 2)
    {
        std::string flag = av[i];
        if (i + 1 >= ac)
            usage_error(flag + " needs a value");
        const char *v = av[i + 1];
        if (flag == "--layers")
            o.layers = positive_int("--layers", v, 3);
        else if (flag == "--re")
            o.re = positive_number("--re", v);
        else if (flag == "--c0-factor")
            o.c0_factor = positive_number("--c0-factor", v);
        else if (flag == "--tau")
            o.tau = positive_number("--tau", v);
        else if (flag == "--columns")
            o.columns = positive_int("--columns", v, 4);
        else if (flag == "--threads")
            o.threads = positive_int("--threads", v, 1);
        else
            usage_error("unknown option " + flag);
    }
    return o;
}

class WaterBlock : public MultiPolygonShape
{
  public:
    WaterBlock(const std::string &name, Real DL, Real DH) : MultiPolygonShape(name)
    {
        std::vector<Vecd> shape{Vecd(0.0, 0.0), Vecd(0.0, DH), Vecd(DL, DH), Vecd(DL, 0.0), Vecd(0.0, 0.0)};
        multi_polygon_.addPolygon(shape, GeometricOps::add);
    }
};

class WallBoundary : public MultiPolygonShape
{
  public:
    WallBoundary(const std::string &name, Real DL, Real DH, Real BW) : MultiPolygonShape(name)
    {
        std::vector<Vecd> outer{Vecd(-BW, -BW), Vecd(-BW, DH + BW), Vecd(DL + BW, DH + BW),
                                Vecd(DL + BW, -BW), Vecd(-BW, -BW)};
        std::vector<Vecd> inner{Vecd(-2.0 * BW, 0.0), Vecd(-2.0 * BW, DH), Vecd(DL + 2.0 * BW, DH),
                                Vecd(DL + 2.0 * BW, 0.0), Vecd(-2.0 * BW, 0.0)};
        multi_polygon_.addPolygon(outer, GeometricOps::add);
        multi_polygon_.addPolygon(inner, GeometricOps::sub);
    }
};
} // namespace

int main(int ac, char *av[])
{
    const Options opt = parse(ac, av);
    // The stock geometry: DH = 1 = 2 B, spacing B / N, walls 4 dx thick.
    const Real DH = 1.0;
    const Real B = 0.5 * DH;
    const Real dx = B / opt.layers;
    const Real DL = opt.columns * dx;
    const Real BW = 4.0 * dx;
    // The flow: U the steady centre-line speed (stock U_max = 1.5 U_f),
    // nu from U B / nu = re, the body force of the steady parabola
    // u = g / (2 nu) y (DH - y), whose maximum g DH^2 / (8 nu) is U.
    const Real rho0_f = 1.0;
    const Real U = 1.5;
    const Real U_f = U / 1.5; // the stock case's reference (mean) speed
    const Real nu = U * B / opt.re;
    const Real mu_f = rho0_f * nu;
    const Real gravity_g = 2.0 * nu * U / (B * B);
    const Real c_f = opt.c0_factor * U;
    const Real end_time = opt.tau * B * B / nu;

    BoundingBoxd system_domain_bounds(Vec2d(-BW, -BW), Vec2d(DL + BW, DH + BW));
    SPHSystem sph_system(system_domain_bounds, dx, static_cast<size_t>(opt.threads));
    sph_system.setLogLevel(4); // errors only

    FluidBody water_block(sph_system, makeShared<WaterBlock>("WaterBody", DL, DH));
    water_block.defineMatterMaterial<WeaklyCompressibleFluid>(rho0_f, c_f);
    water_block.addMaterialProperty<Viscosity>(mu_f);
    water_block.generateParticles<BaseParticles, Lattice>();

    SolidBody wall_boundary(sph_system, makeShared<WallBoundary>("WallBoundary", DL, DH, BW));
    wall_boundary.defineMatterMaterial<Solid>();
    wall_boundary.generateParticles<BaseParticles, Lattice>();

    InnerRelation water_block_inner(water_block);
    ContactRelation water_wall_contact(water_block, {&wall_boundary});
    ComplexRelation water_block_complex(water_block_inner, water_wall_contact);

    // The stock case's methods, in its order.
    Gravity gravity(Vecd(gravity_g, 0.0));
    SimpleDynamics<GravityForce<Gravity>> constant_gravity(water_block, gravity);
    SimpleDynamics<NormalDirectionFromBodyShape> wall_boundary_normal_direction(wall_boundary);
    InteractionWithUpdate<LinearGradientCorrectionMatrixComplex> kernel_correction_complex(water_block_inner, water_wall_contact);
    Dynamics1Level<fluid_dynamics::Integration1stHalfCorrectionWithWallRiemann> pressure_relaxation(water_block_inner, water_wall_contact);
    Dynamics1Level<fluid_dynamics::Integration2ndHalfWithWallNoRiemann> density_relaxation(water_block_inner, water_wall_contact);
    InteractionWithUpdate<fluid_dynamics::DensitySummationComplex> update_density_by_summation(water_block_inner, water_wall_contact);
    InteractionWithUpdate<fluid_dynamics::ViscousForceWithWallCorrection> viscous_force(water_block_inner, water_wall_contact);
    InteractionWithUpdate<fluid_dynamics::TransportVelocityCorrectionCorrectedComplex<AllParticles>>
        transport_velocity_correction(water_block_inner, water_wall_contact);
    ReduceDynamics<fluid_dynamics::AdvectionViscousTimeStep> get_fluid_advection_time_step_size(water_block, U_f);
    ReduceDynamics<fluid_dynamics::AcousticTimeStep> get_fluid_time_step_size(water_block);
    PeriodicAlongAxis periodic_along_x(water_block.getSPHBodyBounds(), xAxis);
    PeriodicConditionUsingCellLinkedList periodic_condition(water_block, periodic_along_x);
    ParticleSorting particle_sorting(water_block);

    sph_system.initializeSystemCellLinkedLists();
    periodic_condition.update_cell_linked_list_.exec();
    sph_system.initializeSystemConfigurations();
    wall_boundary_normal_direction.exec();
    constant_gravity.exec();

    Real &physical_time = *sph_system.getSystemVariableDataByName<Real>("PhysicalTime");
    size_t advection_steps = 0;
    size_t acoustic_steps = 0;
    Real dt_min = MaxReal, Dt_min = MaxReal;

    const auto start = std::chrono::steady_clock::now();
    while (physical_time < end_time)
    {
        Real Dt = get_fluid_advection_time_step_size.exec();
        Dt = SMIN(Dt, end_time - physical_time); // the last one ends at about end_time
        Dt_min = SMIN(Dt_min, Dt);
        update_density_by_summation.exec();
        kernel_correction_complex.exec();
        viscous_force.exec();
        transport_velocity_correction.exec();

        Real relaxation_time = 0.0;
        while (relaxation_time < Dt)
        {
            Real dt = SMIN(get_fluid_time_step_size.exec(), Dt);
            dt_min = SMIN(dt_min, dt);
            pressure_relaxation.exec(dt);
            density_relaxation.exec(dt);
            relaxation_time += dt;
            physical_time += dt;
            acoustic_steps++;
        }
        advection_steps++;

        periodic_condition.bounding_.exec();
        if (advection_steps % 100 == 0 && advection_steps != 1)
        {
            particle_sorting.exec();
        }
        water_block.updateCellLinkedList();
        periodic_condition.update_cell_linked_list_.exec();
        water_block_complex.updateConfiguration();
    }
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    // The profile by row: rows of height dx from the lower wall.
    BaseParticles &fluid = water_block.getBaseParticles();
    const size_t n_fluid = fluid.TotalRealParticles();
    const size_t n_wall = wall_boundary.getBaseParticles().TotalRealParticles();
    const Vecd *pos = fluid.getVariableDataByName<Vecd>("Position");
    const Vecd *vel = fluid.getVariableDataByName<Vecd>("Velocity");
    const int rows = 2 * opt.layers;
    std::vector<double> sum_y(rows, 0.0), sum_u(rows, 0.0);
    std::vector<size_t> count(rows, 0);
    bool finite = true;
    for (size_t i = 0; i < n_fluid; ++i)
    {
        if (!std::isfinite(pos[i][1]) || !std::isfinite(vel[i][0]))
        {
            finite = false;
            continue;
        }
        int r = static_cast<int>(std::floor(pos[i][1] / dx));
        r = r < 0 ? 0 : (r >= rows ? rows - 1 : r);
        sum_y[r] += pos[i][1];
        sum_u[r] += vel[i][0];
        count[r]++;
    }

    const size_t particles = n_fluid + n_wall;
    std::ostringstream js;
    js << std::setprecision(17);
    js << "{\"code\": \"SPHinXsys 9f33297, shearsph_poiseuille_match (stock test_2d_poiseuille_flow methods)\""
       << ", \"layers\": " << opt.layers << ", \"columns\": " << opt.columns
       << ", \"particles\": " << particles << ", \"n_fluid\": " << n_fluid << ", \"n_wall\": " << n_wall
       << ", \"steps\": " << acoustic_steps << ", \"advection_steps\": " << advection_steps
       << ", \"threads\": " << opt.threads << ", \"wall_s\": " << wall_s
       << ", \"particle_steps_per_s\": " << (wall_s > 0.0 ? particles * acoustic_steps / wall_s : 0.0)
       << ", \"t\": " << physical_time << ", \"tau\": " << physical_time * nu / (B * B)
       << ", \"re\": " << opt.re << ", \"c0\": " << c_f << ", \"u\": " << U << ", \"nu\": " << nu
       << ", \"fx\": " << gravity_g << ", \"ly\": " << DH << ", \"dx\": " << dx << ", \"h_over_dx\": "
       << water_block.getSPHAdaptation().ReferenceSmoothingLength() / dx
       << ", \"dt_min\": " << dt_min << ", \"Dt_min\": " << Dt_min
       << ", \"finite\": " << (finite ? "true" : "false") << ", \"profile\": [";
    for (int r = 0; r < rows; ++r)
    {
        js << (r ? ", " : "") << "[";
        if (count[r] > 0)
            js << sum_y[r] / count[r] << ", " << sum_u[r] / count[r] << ", " << count[r];
        else
            js << "null, null, 0";
        js << "]";
    }
    js << "]}";
    std::cout << js.str() << std::endl;
    return finite ? 0 : 1;
}
