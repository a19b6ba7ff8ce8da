/* fix_nfd_history.cpp: fix nfd/history (fix_nfd_history.h).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "fix_nfd_history.h"

#include "pair_nfd.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "modify.h"
#include "neigh_list.h"
#include "utils.h"

#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <string>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

FixNfdHistory::FixNfdHistory(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
    if (narg != 3) error->all(FLERR, "fix nfd/history is internal to pair_style nfd/*: it takes no arguments");
    create_attribute = 1;
    maxexchange_dynamic = 1;
    maxexchange = 1;
    restart_peratom = 1;
    restart_global = 1;
    FixNfdHistory::grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    atom->add_callback(Atom::RESTART);
}

FixNfdHistory::~FixNfdHistory()
{
    atom->delete_callback(id, Atom::GROW);
    atom->delete_callback(id, Atom::RESTART);
}

int FixNfdHistory::setmask()
{
    return FixConst::PRE_EXCHANGE | FixConst::MIN_PRE_EXCHANGE | FixConst::POST_NEIGHBOR | FixConst::MIN_POST_NEIGHBOR;
}

void FixNfdHistory::init()
{
    if (!pair) error->all(FLERR, "fix nfd/history is internal to pair_style nfd/*: define the pair style");
    if (atom->tag_enable == 0) error->all(FLERR, "pair_style nfd/* needs atom IDs (atom_modify id yes)");
    // said once: what a restart file brought back (each contact is held by both its atoms)
    bigint all = 0;
    MPI_Allreduce(&restored, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    if (all > 0 && comm->me == 0)
        utils::logmesg(lmp, fmt::format("fix {} ({}): the history of {} contact(s) restored from the restart "
                                        "file\n", id, style, all / 2));
    if (all > 0) check_restored();
    restored = 0;
    written_coeffs.clear();
    // atoms added by a fix in its pre_exchange must come after this fix stored the history
    for (int k = 0; k < modify->nfix; ++k) {
        if (modify->fix[k] == this) break;
        if (modify->fix[k]->pre_exchange_migrate)
            error->all(FLERR, fmt::format("fix {} migrates atoms before fix nfd/history stores the contact "
                                          "history: define it after pair_coeff", modify->fix[k]->style));
    }
}

bool FixNfdHistory::ready() const { return have_list && nlocal_neigh == atom->nlocal; }

/* list entries -> per-atom partner lists (owned atoms of the last neighbor build) */
void FixNfdHistory::pre_exchange()
{
    if (!have_list) return;
    NeighList *list = pair->list;
    tagint *tag = atom->tag;
    for (int i = 0; i < nlocal_neigh; ++i) clear_partners(i);
    for (int ii = 0; ii < list->inum; ++ii) {
        int i = list->ilist[ii];
        int *jlist = list->firstneigh[i];
        for (int jj = 0; jj < list->numneigh[i]; ++jj) {
            if (!touching(i, jj)) continue;
            int j = jlist[jj] & NEIGHMASK;
            const double *h = value(i, jj);
            add_partner(i, tag[j], h, width);
            if (j < nlocal_neigh) add_partner(j, tag[i], h, width);
        }
    }
    int largest = 0;
    for (int i = 0; i < nlocal_neigh; ++i) largest = npartner[i] > largest ? npartner[i] : largest;
    maxexchange = 1 + (1 + width) * largest;
    for (int i = nlocal_neigh; i < atom->nlocal; ++i) clear_partners(i);
}

/* per-atom partner lists -> the entries of the new neighbor list */
void FixNfdHistory::post_neighbor()
{
    NeighList *list = pair->list;
    tagint *tag = atom->tag;
    nlocal_neigh = atom->nlocal;
    first.assign(nlocal_neigh, 0);
    size_t entries = 0;
    for (int ii = 0; ii < list->inum; ++ii) {
        int i = list->ilist[ii];
        first[i] = entries;
        entries += list->numneigh[i];
    }
    values.assign(width * entries, 0.0);
    touch.assign(entries, 0);
    // matched[i][m]: partner record m of owned atom i went to a list entry (its own, or, for two
    // owned atoms, the other atom's copy did); a record matched by neither is an orphan
    std::vector<std::vector<unsigned char>> matched(nlocal_neigh);
    for (int i = 0; i < nlocal_neigh; ++i) matched[i].assign(npartner[i], 0);
    for (int ii = 0; ii < list->inum; ++ii) {
        int i = list->ilist[ii];
        if (npartner[i] == 0) continue;
        int *jlist = list->firstneigh[i];
        for (int jj = 0; jj < list->numneigh[i]; ++jj) {
            const int j = jlist[jj] & NEIGHMASK;
            tagint jtag = tag[j];
            for (int m = 0; m < npartner[i]; ++m) {
                if (partner[i][m] != jtag) continue;
                std::memcpy(value(i, jj), &partner_values[i][width * m], width * sizeof(double));
                touch[first[i] + jj] = 1;
                matched[i][m] = 1;
                break;
            }
            if (j < nlocal_neigh)
                for (int m = 0; m < npartner[j]; ++m)
                    if (partner[j][m] == tag[i]) matched[j][m] = 1;
        }
    }
    for (int i = 0; i < nlocal_neigh; ++i)
        for (int m = 0; m < npartner[i]; ++m) orphans += matched[i][m] ? 0 : 1;
    have_list = true;
}

/* A 64-bit mix of a contact's two tags and its history's bits (splitmix64 steps). */
static uint64_t copy_hash(tagint low, tagint high, const double *h, int doubles)
{
    uint64_t z = mix64(static_cast<uint64_t>(low)) ^ mix64(static_cast<uint64_t>(high) + 0x632be59bd9b4e019ULL);
    for (int n = 0; n < doubles; ++n) z = mix_double(z, h[n]);
    return z;
}

/* Unpaired copies: each copy of a contact between two ranks adds +-1 by the order of its tags,
 * and its tags' and values' hash to an XOR: the sums cancel exactly when every copy has its twin. */
void FixNfdHistory::census(double *out)
{
    NeighList *list = pair->list;
    tagint *tag = atom->tag;
    bigint mine[3] = {0, orphans, 0};
    uint64_t hash = 0;
    if (have_list) {
        for (int ii = 0; ii < list->inum; ++ii) {
            const int i = list->ilist[ii];
            const int *jlist = list->firstneigh[i];
            for (int jj = 0; jj < list->numneigh[i]; ++jj) {
                if (!touching(i, jj)) continue;
                const int j = jlist[jj] & NEIGHMASK;
                if (j < nlocal_neigh) {
                    ++mine[0];
                    continue;
                }
                const bool lower = tag[i] < tag[j];
                mine[0] += lower ? 1 : 0;
                mine[2] += lower ? 1 : -1;
                hash ^= copy_hash(std::min(tag[i], tag[j]), std::max(tag[i], tag[j]), value(i, jj), width);
            }
        }
    }
    bigint all[3];
    MPI_Allreduce(mine, all, 3, MPI_LMP_BIGINT, MPI_SUM, world);
    uint64_t all_hash = 0;
    MPI_Allreduce(&hash, &all_hash, 1, MPI_UINT64_T, MPI_BXOR, world);
    out[0] = (double) all[0];
    out[1] = (double) all[1];
    out[2] = (double) (all[2] < 0 ? -all[2] : all[2]) + (all_hash != 0 ? 1.0 : 0.0);
}

void FixNfdHistory::grow_arrays(int nmax)
{
    npartner.resize(nmax, 0);
    partner.resize(nmax);
    partner_values.resize(nmax);
}

void FixNfdHistory::copy_arrays(int i, int j, int /*delflag*/)
{
    npartner[j] = npartner[i];
    partner[j] = partner[i];
    partner_values[j] = partner_values[i];
}

int FixNfdHistory::pack_exchange(int i, double *buf)
{
    int m = 0;
    buf[m++] = npartner[i];
    for (int k = 0; k < npartner[i]; ++k) {
        buf[m++] = static_cast<double>(partner[i][k]);
        for (int n = 0; n < width; ++n) buf[m++] = partner_values[i][width * k + n];
    }
    return m;
}

int FixNfdHistory::unpack_exchange(int nlocal, double *buf)
{
    int m = 0;
    clear_partners(nlocal);
    int count = static_cast<int>(buf[m++]);
    for (int k = 0; k < count; ++k) {
        tagint who = static_cast<tagint>(buf[m++]);
        add_partner(nlocal, who, &buf[m], width);
        m += width;
    }
    if (1 + (1 + width) * count > maxexchange) maxexchange = 1 + (1 + width) * count;
    return m;
}

/* Restart files: per atom [its length, npartner, then per partner its ID and the NHIST values]
 * (read_restart keeps the values of every fix in atom->extra[i] one after the other, each led by
 * its own length). Between runs (write_restart) the lists are those post_run stored. During a
 * run (restart N) LAMMPS re-neighbors on the step it writes, so the lists are the history before
 * that step's forces; the continued run recomputes that step from them (setup), so it follows
 * the uninterrupted run all the same. maxsize_restart is called on every rank. */
int FixNfdHistory::maxsize_restart()
{
    int mine = 0, all = 0;
    for (int i = 0; i < atom->nlocal; ++i) mine = npartner[i] > mine ? npartner[i] : mine;
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MAX, world);
    return 2 + (1 + width) * all;
}

int FixNfdHistory::size_restart(int i) { return 2 + (1 + width) * npartner[i]; }

int FixNfdHistory::pack_restart(int i, double *buf)
{
    int m = 1;
    buf[m++] = npartner[i];
    for (int k = 0; k < npartner[i]; ++k) {
        buf[m++] = static_cast<double>(partner[i][k]);
        for (int n = 0; n < width; ++n) buf[m++] = partner_values[i][width * k + n];
    }
    buf[0] = m;
    return m;
}

void FixNfdHistory::unpack_restart(int nlocal, int nth)
{
    const double *extra = atom->extra[nlocal];
    int m = 0;
    for (int k = 0; k < nth; ++k) m += static_cast<int>(extra[m]);
    const int length = static_cast<int>(extra[m++]);
    clear_partners(nlocal);
    const int count = static_cast<int>(extra[m++]);
    // the file's record width (record_width, or a file without the energy block): a file with springs
    // widens a fix that holds none yet, before any record is stored; otherwise each record is fitted
    const int written = count > 0 ? (length - 2) / count - 1 : width;
    if (count > 0 && record_has_springs(written) && !record_has_springs(width) && !have_list)
        set_width(record_width(true) + record_rate_doubles(width));
    if (count > 0 && record_has_rate(written) && !record_has_rate(width) && !have_list)
        set_width(width + NRATE);      // the contacts' R, fixed at their first touch
    if (count > 0 && record_has_relaxing(written) && !record_has_relaxing(width) && !have_list)
        set_width(record_width(record_has_springs(written) || record_has_springs(width)) + NRATE_RELAXING);
    std::vector<double> record(width, 0.0);
    for (int k = 0; k < count; ++k) {
        const tagint who = static_cast<tagint>(extra[m++]);
        ContactEnergy::restride(&extra[m], written, record.data(), width);
        add_partner(nlocal, who, record.data(), width);
        m += written;
    }
    restored += count;
    if (1 + (1 + width) * count > maxexchange) maxexchange = 1 + (1 + width) * count;
}

/* Global restart data: [ntypes, then per atom type the 64-bit fingerprint of its pair_coeff
 * (PairNfd::coeff_fingerprint)], as raw 64-bit words led by their size in bytes (proc 0 writes,
 * every rank reads the broadcast copy in restart()). */
void FixNfdHistory::write_restart(FILE *fp)
{
    refresh_springs();
    std::vector<uint64_t> words = coeff_fingerprints();
    if (comm->me == 0) {
        const int size = static_cast<int>(words.size() * sizeof(uint64_t));
        std::fwrite(&size, sizeof(int), 1, fp);
        std::fwrite(words.data(), sizeof(uint64_t), words.size(), fp);
    }
}

void FixNfdHistory::restart(char *buf)
{
    uint64_t ntypes = 0;
    std::memcpy(&ntypes, buf, sizeof(ntypes));
    written_coeffs.assign(1 + ntypes, 0);
    std::memcpy(written_coeffs.data(), buf, (1 + ntypes) * sizeof(uint64_t));
}

double FixNfdHistory::memory_usage()
{
    double bytes = (double) values.capacity() * sizeof(double) + (double) touch.capacity() +
                   (double) first.capacity() * sizeof(size_t);
    for (size_t i = 0; i < partner.size(); ++i)
        bytes += (double) partner[i].capacity() * sizeof(tagint) +
                 (double) partner_values[i].capacity() * sizeof(double);
    return bytes;
}

/* [ntypes, then the fingerprint of each type's pair_coeff] of the pair style now (no pair: [0]). */
std::vector<uint64_t> FixNfdHistory::coeff_fingerprints() const
{
    const int ntypes = pair && pair->allocated ? atom->ntypes : 0;
    std::vector<uint64_t> words(1 + ntypes, 0);
    words[0] = static_cast<uint64_t>(ntypes);
    for (int t = 1; t <= ntypes; ++t) words[t] = pair->coeff_fingerprint(t);
    return words;
}

/* After a restart brought histories back (init of the run): the pair_coeff of each type must be
 * the one the histories were made under, otherwise the contacts go on from a delta_max, P_max,
 * delta_res, K_u of other constants -- said in a warning naming the types (a deliberate change
 * stays possible). A file without fingerprints (none written) is not checked. */
void FixNfdHistory::check_restored()
{
    if (written_coeffs.empty() || comm->me != 0) return;
    const std::vector<uint64_t> now = coeff_fingerprints();
    std::string differ;
    int count = 0;
    if (now.size() != written_coeffs.size()) {
        differ = "the number of atom types changed";
    } else {
        for (size_t t = 1; t < now.size(); ++t)
            if (now[t] != written_coeffs[t]) differ += (count++ ? " " : "") + std::to_string(t);
        if (count) differ = fmt::format("the pair_coeff of atom type{} {} differ{} from the restart file's",
                                        count > 1 ? "s" : "", differ, count > 1 ? "" : "s");
    }
    if (!differ.empty())
        error->warning(FLERR, fmt::format("pair_style {}: {}: the restored contact histories were made under other "
                                          "constants and go on from them", pair->name(), differ));
}

void FixNfdHistory::clear_partners(int i)
{
    npartner[i] = 0;
    partner[i].clear();
    partner_values[i].clear();
}

void FixNfdHistory::add_partner(int i, tagint who, const double *h, int doubles)
{
    partner[i].push_back(who);
    partner_values[i].insert(partner_values[i].end(), h, h + doubles);
    ++npartner[i];
}

void FixNfdHistory::set_width(int doubles)
{
    if (doubles == width) return;
    auto restride = [&](std::vector<double> &v) {
        const size_t records = v.size() / width;
        std::vector<double> out(records * doubles, 0.0);
        for (size_t r = 0; r < records; ++r) ContactEnergy::restride(&v[r * width], width, &out[r * doubles], doubles);
        v.swap(out);
    };
    for (auto &v : partner_values) restride(v);
    restride(values);
    width = doubles;
}

/* Before a restart file is written (every rank, before the per-atom records are packed): the
 * per-atom records hold the history the last re-neighboring stored -- during a run, the history
 * before this step's forces, which the continued run recomputes (setup) -- and the springs and
 * the energy block are set to their values after this step's forces, which the set-up step evaluates without advancing
 * them (as LAMMPS's granular styles do). A contact that began on this step gets a record of a
 * virgin normal history with its springs. Between runs (post_run stored everything) nothing
 * changes. */
void FixNfdHistory::refresh_springs()
{
    if (!have_list || !pair || !pair->list) return;
    NeighList *list = pair->list;
    tagint *tag = atom->tag;
    std::vector<double> fresh(width, 0.0);
    auto refresh = [&](int owner, tagint who, const double *h) {
        for (int m = 0; m < npartner[owner]; ++m)
            if (partner[owner][m] == who) {
                std::copy(h + NHIST, h + width, &partner_values[owner][width * m + NHIST]);
                return;
            }
        std::copy(h + NHIST, h + width, fresh.begin() + NHIST);
        add_partner(owner, who, fresh.data(), width);
    };
    for (int ii = 0; ii < list->inum; ++ii) {
        const int i = list->ilist[ii];
        const int *jlist = list->firstneigh[i];
        for (int jj = 0; jj < list->numneigh[i]; ++jj) {
            if (!touching(i, jj)) continue;
            const int j = jlist[jj] & NEIGHMASK;
            refresh(i, tag[j], value(i, jj));
            if (j < nlocal_neigh) refresh(j, tag[i], value(i, jj));
        }
    }
}

}    // namespace nfdcal_lammps
