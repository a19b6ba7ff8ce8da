/* compute_nfd_contacts.cpp: compute nfd/contacts (compute_nfd_contacts.h).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "compute_nfd_contacts.h"

#include "fix_nfd_history.h"
#include "pair_nfd.h"

#include "error.h"
#include "force.h"
#include "update.h"

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

ComputeNfdContacts::ComputeNfdContacts(LAMMPS *lmp, int narg, char **arg) : Compute(lmp, narg, arg)
{
    if (narg != 3) error->all(FLERR, "compute nfd/contacts takes no arguments: compute ID all nfd/contacts");
    vector_flag = 1;
    size_vector = 3;
    extvector = 0;
    vector = values;
}

void ComputeNfdContacts::init()
{
    pair = dynamic_cast<PairNfd *>(force->pair);
    if (!pair || !pair->contact_history())
        error->all(FLERR, "compute nfd/contacts needs pair_style nfd/vz (nfd/vz-table, nfd/hertz, nfd/thornton, "
                          "nfd/walton-braun) with its pair_coeff");
}

void ComputeNfdContacts::compute_vector()
{
    invoked_vector = update->ntimestep;
    pair->contact_history()->census(values);
}

}    // namespace nfdcal_lammps
