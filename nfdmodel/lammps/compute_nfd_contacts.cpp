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
#include "utils.h"

#include <string>

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
    if (pair && pair->contact_history()) return;
    std::string styles;
    for (int code = 0; code < NFD_LAW_COUNT; ++code)
        if (NfdLaw::of(code)) styles += (styles.empty() ? "" : ", ") + NfdLaw::of(code)->pair_style;
    error->all(FLERR,
               fmt::format("compute nfd/contacts needs a pair_style nfd/<law> ({}) with its pair_coeff", styles));
}

void ComputeNfdContacts::compute_vector()
{
    invoked_vector = update->ntimestep;
    pair->contact_history()->census(values);
}

}    // namespace nfdcal_lammps
