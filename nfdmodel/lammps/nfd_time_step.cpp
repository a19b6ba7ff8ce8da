/* nfd_time_step.cpp: the time step against the contacts' durations (nfd_time_step.h).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "nfd_time_step.h"

#include "../nfd_kernel.h"

#include "comm.h"
#include "error.h"
#include "lammps.h"
#include "update.h"

#include <mpi.h>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

void NfdTimeStep::see(LAMMPS *lmp, const std::string &who, double t_c, double v)
{
    const double steps = t_c / lmp->update->dt;
    if (!(steps < fewest)) return;       // a contact at rest (t_c infinite) or a longer one
    fewest = steps;
    time = t_c;
    speed = v;
    if (lmp->comm->me == 0 && !warned && fewest < NFD_STEPS_PER_CONTACT_MIN) warn(lmp, who);
}

void NfdTimeStep::end_run(LAMMPS *lmp, const std::string &who)
{
    struct {
        double value;
        int rank;
    } mine{fewest, lmp->comm->me}, least{INFINITY, 0};
    MPI_Allreduce(&mine, &least, 1, MPI_DOUBLE_INT, MPI_MINLOC, lmp->world);
    double contact[2] = {time, speed};
    MPI_Bcast(contact, 2, MPI_DOUBLE, least.rank, lmp->world);
    if (lmp->comm->me == 0 && !warned && least.value < NFD_STEPS_PER_CONTACT_MIN) {
        fewest = least.value;
        time = contact[0];
        speed = contact[1];
        warn(lmp, who);
    }
    fewest = INFINITY;
}

void NfdTimeStep::warn(LAMMPS *lmp, const std::string &who)
{
    warned = true;
    lmp->error->warning(FLERR, fmt::format("{}: a contact at normal speed {:.4g} m/s lasts about {:.3g} steps (its "
                                           "estimated contact time {:.3g} s at timestep {:.4g} s), fewer than {} per "
                                           "contact: its e and P_max are inaccurate; use timestep <= {:.3g} s",
                                           who, speed, fewest, time, lmp->update->dt, NFD_STEPS_PER_CONTACT_MIN,
                                           time / NFD_STEPS_PER_CONTACT_MIN));
}

}    // namespace nfdcal_lammps
