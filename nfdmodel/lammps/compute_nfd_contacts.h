/* compute_nfd_contacts.h: compute ID all nfd/contacts, the contact census of pair_style nfd/<law>
 * (FixNfdHistory::census), a global vector: 1 contacts holding a history (each once, over all
 * ranks), 2 orphan history records since the start (a history lost at re-neighboring or
 * migration: must be 0), 3 unpaired or differing copies of contacts between two ranks (must be 0).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#ifndef NFD_LAMMPS_COMPUTE_NFD_CONTACTS_H
#define NFD_LAMMPS_COMPUTE_NFD_CONTACTS_H

#include "compute.h"

namespace nfdcal_lammps {

class PairNfd;

class ComputeNfdContacts : public LAMMPS_NS::Compute {
 public:
    ComputeNfdContacts(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
    void init() override;
    void compute_vector() override;

 private:
    PairNfd *pair = nullptr;
    double values[3] = {0.0, 0.0, 0.0};
};

}    // namespace nfdcal_lammps

#endif
