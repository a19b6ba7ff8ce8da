/* nfd_time_step.h: whether the time step resolves the contacts of a pair style or wall fix.
 *
 * A contact starting at normal speed v lasts about t_c (NfdLaw::contact_time: Hertz's elastic
 * impact, Johnson 1985 eq. 11.24, or the Walton-Braun springs' half periods); with fewer than
 * NFD_STEPS_PER_CONTACT_MIN steps of the run's timestep in it, e and P_max are inaccurate (the
 * leap-frog's error is O(dt^2); nfdmodel.collide warns at the same number). One LAMMPS WARNING per
 * pair style or wall fix, naming the steps per contact and a timestep that resolves it: at once when
 * rank 0 sees such a contact, else at the end of the run (the fewest steps of every rank).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#ifndef NFD_LAMMPS_TIME_STEP_H
#define NFD_LAMMPS_TIME_STEP_H

#include <cmath>
#include <string>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace nfdcal_lammps {

class NfdTimeStep {
 public:
    /* The start of a run: no contact seen yet (a warning given stays given). */
    void begin_run() { fewest = INFINITY; }

    /* A contact starting at normal speed v [m/s], estimated to last t_c [s], of the style who
     * ("pair_style nfd/vz", "fix wall (nfd/wall/vz)"). */
    void see(LAMMPS_NS::LAMMPS *lmp, const std::string &who, double t_c, double v);

    /* The end of a run, on every rank: the fewest steps per contact of all ranks, warned of on rank 0
     * unless warned already. */
    void end_run(LAMMPS_NS::LAMMPS *lmp, const std::string &who);

 private:
    void warn(LAMMPS_NS::LAMMPS *lmp, const std::string &who);

    bool warned = false;          // rank 0: the warning was given
    double fewest = INFINITY;     // this rank's fewest steps per contact this run
    double time = 0.0, speed = 0.0;    // that contact's estimated duration [s] and normal speed [m/s]
};

}    // namespace nfdcal_lammps

#endif
