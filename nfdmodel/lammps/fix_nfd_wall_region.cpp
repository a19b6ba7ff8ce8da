/* fix_nfd_wall_region.cpp: fix nfd/wall/region/<law> (fix_nfd_wall_region.h).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "fix_nfd_wall_region.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "region.h"
#include "utils.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

FixNfdWallRegion::FixNfdWallRegion(LAMMPS *lmp, int narg, char **arg, const NfdLaw *law) :
    FixNfdWall(lmp, narg, arg, law, 4)
{
    const char *geometry = "REGION-ID (the ID of a region)";
    if (narg < 5) error->all(FLERR, fmt::format("{}: need {} and the material", who(), geometry));
    region_id = arg[3];
    region = find_region();
    read_constants(narg, arg, geometry);
    allocate(region->tmax, true);
    FixNfdWallRegion::grow_arrays(atom->nmax);
    for (int i = 0; i < atom->nmax; ++i) FixNfdWallRegion::set_arrays(i);
    scratch.assign(row, 0.0);
    restart_global = 1;
}

Region *FixNfdWallRegion::find_region() const
{
    Region *found = domain->get_region_by_id(region_id);
    if (!found)
        error->all(FLERR, fmt::format("{}: REGION-ID out of range: need the ID of a defined region, got '{}'", who(),
                                      region_id));
    if (found->tmax < 1)
        error->all(FLERR, fmt::format("{}: region {} (style {}) has no surface an atom can touch", who(), region_id,
                                      found->style));
    return found;
}

void FixNfdWallRegion::init()
{
    FixNfdWall::init();
    Region *now = find_region();
    if (now->tmax > slots)
        error->all(FLERR, fmt::format("{}: region {} (style {}) can touch an atom {} times at once, the fix keeps {} "
                                      "histories per atom: define the fix again after the region", who(), region_id,
                                      now->style, now->tmax, slots));
    if (now != region) {
        region = now;
        region->reset_vel();
    }
    if (motion_from_restart_failed) {
        if (comm->me == 0)
            error->warning(FLERR, fmt::format("{}: the restart file's motion of region {} does not fit the region: "
                                              "its motion starts afresh", who(), region_id));
        region->reset_vel();
        motion_from_restart_failed = false;
    }
    // the screen's distances (fix_nfd_wall_region.h): a block's, a sphere's and a cylinder's from either
    // side, a cone's from inside; other styles, open faces and a region that moves or changes shape are
    // asked at every step
    const char *style = region->style;
    const bool lipschitz = std::strcmp(style, "block") == 0 || std::strcmp(style, "sphere") == 0 ||
                           std::strcmp(style, "cylinder") == 0 || (std::strcmp(style, "cone") == 0 && region->interior);
    screen = lipschitz && !region->openflag && !region->dynamic && !region->varshape;
    facets = region->interior ? region->cmax : 1;
    for (int i = 0; i < atom->nmax; ++i) reach[4 * i + 3] = -1.0;    // the region may be another one
}

/* Atom i's contacts at radius R. The screen: an atom tested at (x0, y0, z0) with no facet within c = 2R
 * is skipped while it stays within (c - R)/2 of there (half the slack, far beyond round-off: a facet is
 * then farther than R from it); an atom with a facet within 2R is asked at every step, and tested again
 * once it moved R/2. The test asks for every facet (an infinite cutoff) and trusts "none within 2R" only
 * when every facet answered (a sphere's centre or a cylinder's or cone's axis, where LAMMPS leaves the
 * curved facet out, is not a test). The contacts found are those of the region at R, whether or not the
 * atom was tested. */
int FixNfdWallRegion::touching(int i, double R)
{
    const double *x = atom->x[i];
    if (!screen) return region->match(x[0], x[1], x[2]) ? region->surface(x[0], x[1], x[2], R) : 0;
    double *seen = reach.data() + 4 * static_cast<size_t>(i);
    const double dx = x[0] - seen[0], dy = x[1] - seen[1], dz = x[2] - seen[2];
    const double slack = 0.5 * (seen[3] > 0.0 ? seen[3] - R : R);
    if (seen[3] >= 0.0 && slack > 0.0 && dx * dx + dy * dy + dz * dz < slack * slack) {
        if (seen[3] > 0.0 && !held[i]) return -1;
        return region->match(x[0], x[1], x[2]) ? region->surface(x[0], x[1], x[2], R) : 0;
    }
    if (!region->match(x[0], x[1], x[2])) {
        seen[3] = -1.0;
        return 0;
    }
    seen[0] = x[0];
    seen[1] = x[1];
    seen[2] = x[2];
    const double c = 2.0 * R;
    const int answered = region->surface(x[0], x[1], x[2], std::numeric_limits<double>::infinity());
    bool far = answered == facets;
    for (int k = 0; k < answered; ++k) far = far && region->contact[k].r >= c;     // a NaN is not far
    if (far) {                                    // none within 2R, so none within R
        seen[3] = c;
        return 0;
    }
    seen[3] = 0.0;
    return region->surface(x[0], x[1], x[2], R);
}

void FixNfdWallRegion::match_slots(int i, int nc)
{
    double *own = history[i];
    // each contact already in its slot and the next slot empty (slots fill from the first): nothing moves
    int placed = 0;
    while (placed < nc && own[placed * stride] == region->contact[placed].iwall + 1.0) ++placed;
    if (placed == nc && (nc == slots || own[nc * stride] == 0.0)) return;
    for (int k = 0; k < nc; ++k) {
        double *slot = scratch.data() + k * stride;
        const double tag = region->contact[k].iwall + 1.0;
        int s = 0;
        while (s < slots && own[s * stride] != tag) ++s;
        if (s < slots) {
            for (int n = 0; n < stride; ++n) slot[n] = own[s * stride + n];
        } else {              // a new contact: its history starts at zero
            slot[0] = tag;
            for (int n = 1; n < stride; ++n) slot[n] = 0.0;
        }
    }
    for (int n = 0; n < nc * stride; ++n) own[n] = scratch[n];
    for (int n = nc * stride; n < row; ++n) own[n] = 0.0;
}

void FixNfdWallRegion::post_force(int /*vflag*/)
{
    double **x = atom->x;
    double *radius = atom->radius;
    int *mask = atom->mask;
    double v_wall[3] = {0.0, 0.0, 0.0};
    const bool moving = region->dynamic_check() != 0;
    if (moving) {                   // the region's position and velocity at this step
        region->prematch();
        region->set_velocity();
    }
    begin_forces();
    for (int i = 0; i < atom->nlocal; ++i) {
        if (!(mask[i] & groupbit)) continue;
        const int nc = touching(i, radius[i]);
        if (nc < 0) continue;         // no facet within reach, no history
        if (nc > slots)
            error->one(FLERR, fmt::format("{}: atom {} touches {} facets of region {} at once, more than the {} "
                                          "this region style allows (its tmax): the atom is too large for the "
                                          "region", who(), atom->tag[i], nc, region_id, slots));
        if (nc > 0 || held[i]) {      // else no contact now nor before
            match_slots(i, nc);
            note_held(i);
        }
        for (int k = 0; k < nc; ++k) {
            const Region::Contact &touch = region->contact[k];
            double *stored = history[i] + k * stride + 1;
            const double delta = radius[i] - touch.r;
            if (!(delta > 0.0)) {
                for (int n = 0; n < width; ++n) stored[n] = 0.0;
                continue;
            }
            if (!(touch.r > 0.0))
                error->one(FLERR, fmt::format("{}: the centre of atom {} lies on the surface of region {}: no "
                                              "contact normal (overlap = its radius {:.6g} m)", who(), atom->tag[i],
                                              region_id, radius[i]));
            // the region's curvature radius at the point (0: flat; negative: concave), as LAMMPS's
            const double R_star = touch.radius == 0.0 ? radius[i] :
                                                        radius[i] * touch.radius / (radius[i] + touch.radius);
            if (!(R_star > 0.0) || !std::isfinite(R_star))
                error->one(FLERR, fmt::format("{}: atom {} of radius {:.6g} m does not fit the concave surface of "
                                              "region {} (curvature radius {:.6g} m): need a radius < {:.6g} m", who(),
                                              atom->tag[i], radius[i], region_id, -touch.radius, -touch.radius));
            const double r_inverse = 1.0 / touch.r;
            const double n[3] = {touch.delx * r_inverse, touch.dely * r_inverse, touch.delz * r_inverse};
            if (moving) region->velocity_contact(v_wall, x[i], k);
            contact(i, delta, n, R_star, v_wall, stored);
        }
    }
    end_forces();
}

void FixNfdWallRegion::grow_arrays(int nmax)
{
    FixNfdWall::grow_arrays(nmax);
    reach.resize(4 * static_cast<size_t>(nmax), -1.0);
}

void FixNfdWallRegion::copy_arrays(int i, int j, int delflag)
{
    FixNfdWall::copy_arrays(i, j, delflag);
    for (int n = 0; n < 4; ++n) reach[4 * j + n] = reach[4 * i + n];
}

void FixNfdWallRegion::set_arrays(int i)
{
    FixNfdWall::set_arrays(i);
    reach[4 * i + 3] = -1.0;
}

/* An atom arriving from another rank or from a restart file: nothing known of its reach. */
int FixNfdWallRegion::unpack_exchange(int nlocal, double *buf)
{
    reach[4 * nlocal + 3] = -1.0;
    return FixNfdWall::unpack_exchange(nlocal, buf);
}

void FixNfdWallRegion::unpack_restart(int nlocal, int nth)
{
    FixNfdWall::unpack_restart(nlocal, nth);
    reach[4 * nlocal + 3] = -1.0;
}

double FixNfdWallRegion::memory_usage()
{
    return FixNfdWall::memory_usage() + (double) atom->nmax * 4 * sizeof(double);
}

/* The region's motion (its displacement and angle at this step), as LAMMPS's regions write it. */
void FixNfdWallRegion::write_restart(FILE *fp)
{
    if (comm->me != 0) return;
    int length = 0;
    region->length_restart_string(length);
    fwrite(&length, sizeof(int), 1, fp);
    region->write_restart(fp);
}

void FixNfdWallRegion::restart(char *buf)
{
    int n = 0;
    if (!region->restart(buf, n)) motion_from_restart_failed = true;
}

}    // namespace nfdcal_lammps
