/* fix_nfd_wall_region.h: fix nfd/wall/region/<law> (nfd/wall/region/hertz, nfd/wall/region/vz,
 * ...), a rigid wall of the surface of a LAMMPS region with the law of the pair styles.
 *
 *     fix ID group nfd/wall/region/vz REGION-ID E nu sigma_y Ca_hat Kc_hat [window P_max/P_Y]
 *     fix ID group nfd/wall/region/<law> REGION-ID <the constants of fix nfd/wall/<law>>
 *     ... [wall_material E_w nu_w] [pair_constants ...]   (the wall's elastic material and the constants
 *         calibrated for the sphere on it, as fix nfd/wall/<law>)
 *     ... [damping ...] [tangential ...] [rolling ...] [twisting ...]   (nfd_models.h, optional)
 *     ... [energy]   (the energy block kept, as fix nfd/wall/<law>)
 *
 * The contacts are LAMMPS's own (Region::surface, as fix wall/gran/region finds them): each atom
 * of the group whose centre the region holds (Region::match) touches each facet of the region's
 * surface that lies closer than its radius R (a block from inside: up to 3 faces at a corner; from
 * outside: the nearest point, on a face, an edge or a corner; a cylinder from inside: its side and
 * its caps; a sphere: one). A contact at distance r from the surface point has overlap
 * delta = R - r, the normal from that point to the centre, and the effective radius
 * R* = R r_c / (R + r_c) of the region's curvature radius r_c at the point as LAMMPS's regions give
 * it (0 a flat, face, edge or corner: R* = R; a sphere's radius, negative from inside; a cylinder's
 * side 2 r_cyl, negative from inside); the law is the plane wall's (FixNfdWall::contact: E* =
 * E / (1 - nu^2), first yield in the sphere, the wall rigid, k_t NULL = 8 G / (2 - nu), torques
 * about the centre with arm R), so the fix equals fix wall/gran/region of the same models with the
 * sphere's E doubled. A moving or rotating region (region ... move/rotate, or a variable shape)
 * moves the wall: the relative velocity takes the wall's velocity at the contact
 * (Region::velocity_contact); the wall has no spin in the rolling and twisting models (as in
 * wall/gran/region).
 *
 * The reach screen (touching()): a static region without open faces of style block, sphere or cylinder
 * (side in or out) or cone (side in) is asked only for the atoms near its surface; the contacts are
 * those of asking for every atom at every step. It holds where the distance LAMMPS's region reports for
 * each facet (Region::surface_interior/surface_exterior) is at least a function of the atom's position
 * that changes no faster than the atom moves (1-Lipschitz) and the facets within the cutoff are all
 * reported: a block's faces from inside (each face's plane, the nearest of which is the Euclidean
 * distance to the box) and its nearest point from outside; a sphere's |r - r_s| either side; a cylinder's
 * side r_cyl - r and its caps' planes from inside, the nearest point of the solid from outside; a cone
 * from inside, its side the distance to the generating segment in the atom's meridian plane (the
 * Euclidean distance to the surface of revolution), its caps their planes' distance (a lower bound of
 * the distance to the disc, 1-Lipschitz as well). Where LAMMPS leaves a facet out (a sphere's centre, a
 * cylinder's or cone's axis: r = 0) the atom is asked at every step until it has moved R/2 and is
 * tested again. Not screened: a cone from outside (its nearest point on the axis divides 0 by 0, and
 * about y and z is then left unset), open faces (every atom then matches, and a cylinder's or cone's
 * nearest point from outside divides by 0 on the axis), the other styles (prism, plane, union, ... :
 * not argued), a moving or shape-changing region.
 *
 * History: one per contact, keyed by the region's facet (Contact::iwall), kept for as many contacts
 * as the region style can touch at once (Region::tmax: a block 3 from inside, 1 from outside); an
 * atom touching more facets at once (a sphere wider than the box it is in) stops the run with an
 * error naming it. A facet the atom leaves loses its history; an atom the region does not hold
 * touches nothing. The histories travel with the atom between MPI ranks and go into restart files
 * (read back by a fix of the same ID and style defined after read_restart), with the region's
 * motion (as wall/gran/region).
 *
 * Outputs: the global scalar, the sum of the contacts' normal forces [N]; the vector [1], the
 * contacts; the per-atom array, slot after slot (Region::tmax slots): 1 the facet (iwall + 1; 0 an
 * empty slot), then the history of fix nfd/wall (2-6 delta_max ... a_e_max, with models 7-14 the
 * springs and the last contact radius; with energy, then the energy block).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#ifndef NFD_LAMMPS_FIX_NFD_WALL_REGION_H
#define NFD_LAMMPS_FIX_NFD_WALL_REGION_H

#include "fix_nfd_wall.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {
class Region;
}

namespace nfdcal_lammps {

class FixNfdWallRegion : public FixNfdWall {
 public:
    FixNfdWallRegion(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg, const NfdLaw *law);

    void init() override;
    void post_force(int vflag) override;
    void write_restart(FILE *fp) override;
    void restart(char *buf) override;

    void grow_arrays(int nmax) override;
    void copy_arrays(int i, int j, int delflag) override;
    void set_arrays(int i) override;
    int unpack_exchange(int nlocal, double *buf) override;
    void unpack_restart(int nlocal, int nth) override;
    double memory_usage() override;

 private:
    /* The region of the ID, or an error naming the parameter. */
    LAMMPS_NS::Region *find_region() const;
    /* Atom i's slots rearranged to the region's nc contacts (slot k: contact k), each keeping the
     * history of its facet or starting at zero; the other slots emptied. */
    void match_slots(int i, int nc);
    /* Atom i's contacts with the region (Region::match, then Region::surface at its radius R): their number,
     * region->contact filled; or -1, no facet within R (the reach screen: region->contact untouched). */
    int touching(int i, double R);

    std::string region_id;
    LAMMPS_NS::Region *region = nullptr;
    bool motion_from_restart_failed = false;
    std::vector<double> scratch;    // one atom's row while its slots are rearranged
    /* The reach screen (the styles above, whose facet distances are Euclidean or a 1-Lipschitz lower bound
     * of it: an atom moves at least as far as its distance to a facet changes): per atom x0, y0, z0 and c,
     * where c > 0 says no facet lies within c of (x0, y0, z0), 0 that one did, < 0 nothing known; facets,
     * how many the region reports at an infinite cutoff when it leaves none out (Region::cmax from
     * inside, the nearest point from outside). */
    bool screen = false;
    int facets = 0;
    std::vector<double> reach;
};

}    // namespace nfdcal_lammps

#endif
