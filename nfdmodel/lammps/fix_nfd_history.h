/* fix_nfd_history.h: fix nfd/history, the per-contact history of a pair_style nfd/<law> (internal:
 * the pair style creates it, under the ID of its law, NfdLaw::history_id).
 *
 * During a run the history is stored per neighbor-list entry (value(i, jj)); before atoms are
 * exchanged (pre_exchange) and at the end of a run (post_run) it is copied to per-atom lists of
 * (partner ID, values) -- with newton off a contact of two owned atoms goes to both -- which
 * travel with the atoms (pack/unpack_exchange, copy_arrays); after the next neighbor build
 * (post_neighbor) each list entry takes the values its partner ID had, or zeros. The per-atom
 * lists also go into restart files (pack_restart) and come back when the pair style, re-issued
 * after read_restart, creates this fix again under the same ID (unpack_restart); with them goes
 * a fingerprint of each atom type's pair_coeff (write_restart / restart), so that a continuation
 * under other constants is warned about (check_restored).
 *
 * Each record holds width() doubles: the nfd_history (NHIST), then, when the pair style has
 * contact models (nfd_models.h), the nfd_friction_history (NFRICTION), then the energy block
 * (nfd_energy.h: NENERGY, with models NENERGY_MODELS). A restart file of any of these widths, or of
 * one without the energy block, is read into the width of the pair style part by part
 * (ContactEnergy::restride: the springs of a frictionless file start at zero; a frictionless
 * continuation drops them; a file without energies starts them at zero).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#ifndef NFD_LAMMPS_FIX_NFD_HISTORY_H
#define NFD_LAMMPS_FIX_NFD_HISTORY_H

#include "fix.h"
#include "nfd_energy.h"

#include <cstdint>
#include <vector>

namespace nfdcal_lammps {

class PairNfd;

class FixNfdHistory : public LAMMPS_NS::Fix {
 public:
    FixNfdHistory(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
    ~FixNfdHistory() override;

    int setmask() override;
    void init() override;
    void setup_post_neighbor() override { post_neighbor(); }
    void min_pre_exchange() override { pre_exchange(); }
    void min_post_neighbor() override { post_neighbor(); }
    void post_run() override { pre_exchange(); }
    void pre_exchange() override;
    void post_neighbor() override;

    void grow_arrays(int nmax) override;
    void copy_arrays(int i, int j, int delflag) override;
    void set_arrays(int i) override { clear_partners(i); }
    int pack_exchange(int i, double *buf) override;
    int unpack_exchange(int nlocal, double *buf) override;
    int maxsize_restart() override;
    int size_restart(int i) override;
    int pack_restart(int i, double *buf) override;
    void unpack_restart(int nlocal, int nth) override;
    void write_restart(FILE *fp) override;
    void restart(char *buf) override;
    double memory_usage() override;

    /* The contact census of this step over all ranks (collective; compute nfd/contacts): [0]
     * contacts holding a history, each once; [1] orphan history records since the fix was created
     * (records that found no neighbor-list entry at re-neighboring: a lost history); [2] unpaired
     * or differing copies now (with newton off a contact between atoms of two ranks is held by
     * both, and the two copies must be the same). */
    void census(double *out);

    // for the pair style: the history of list entry jj of owned atom i (width() doubles)
    double *value(int i, int jj) { return &values[width * (first[i] + jj)]; }
    int stride() const { return width; }
    /* record_width(models) (nfd_energy.h): the stored records are re-strided (the springs of records
     * that had none start at zero) */
    void set_width(int doubles);
    bool touching(int i, int jj) const { return touch[first[i] + jj] != 0; }
    void set_touching(int i, int jj, bool on) { touch[first[i] + jj] = on ? 1 : 0; }
    bool ready() const;

    PairNfd *pair = nullptr;

 private:
    std::vector<uint64_t> coeff_fingerprints() const;
    void check_restored();
    void clear_partners(int i);
    void add_partner(int i, LAMMPS_NS::tagint who, const double *h, int doubles);
    void refresh_springs();

    std::vector<int> npartner;
    std::vector<std::vector<LAMMPS_NS::tagint>> partner;
    std::vector<std::vector<double>> partner_values;
    LAMMPS_NS::bigint orphans = 0;
    LAMMPS_NS::bigint restored = 0;          // partner records read from a restart file
    std::vector<uint64_t> written_coeffs;    // the restart file's [ntypes, fingerprint per type]
    std::vector<size_t> first;               // per owned atom: its first list entry
    int width = record_width(false);         // doubles per record (set_width)
    std::vector<double> values;              // width per list entry
    std::vector<unsigned char> touch;        // 1: the entry holds a contact's history
    int nlocal_neigh = 0;
    bool have_list = false;
};

}    // namespace nfdcal_lammps

#endif
