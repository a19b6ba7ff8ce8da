"""What a converged step tells about the contact: nodal pressure and the contact radius.

The exact active set gives the contact reactions lambda_i [N] at the surface nodes; from them
the pressure (lumped recovery), and from pressure or gap the contact edge with sub-element
accuracy (Hertz asymptotics at a smooth edge: Johnson 1985, Contact Mechanics, eqs. 4.23 and
4.47). Measured against Hertz in results/hertz/mesh_ladder.csv.
"""
import numpy as np

CONTACT_RADIUS_METHODS = ("pressure", "gap", "node")


def contact_radius_from_gap(r, gap, active, n_skip=1):
    """Contact edge from the gap of the open nodes next to the contact [m].

    Outside a smooth (Hertz-like) contact the gap grows like (r - a)^(3/2) (Johnson 1985,
    eq. 4.47 expanded at r = a), so g^(2/3) is linear in r near the edge: extrapolate the line
    through two open nodes to g = 0. The first ``n_skip`` open node(s) are skipped (their gap is
    distorted by the element cut at the edge); the result is clamped to [r of the outermost
    contact node - its spacing, r of the first open node]. Falls back to the outermost contact
    node when there are too few open nodes.
    """
    r, gap, active = np.asarray(r), np.asarray(gap), np.asarray(active, dtype=bool)
    idx = np.flatnonzero(active)
    if idx.size == 0:
        return 0.0
    last = idx[-1]
    i1, i2 = last + 1 + n_skip, last + 2 + n_skip
    if i2 >= r.size:
        return float(r[last])
    s1, s2 = np.maximum(gap[[i1, i2]], 0.0) ** (2.0 / 3.0)
    if not s2 > s1:
        return float(r[last])
    edge = r[i1] - s1 * (r[i2] - r[i1]) / (s2 - s1)
    lower = r[last] - (r[last] - r[idx[-2]] if idx.size > 1 else 0.0)
    return float(np.clip(edge, lower, r[last + 1]))


def contact_radius_from_pressure(r, pressure, active, n_fit=10, n_skip=3):
    """Contact edge from the pressure of the outer contact nodes [m].

    Hertz: p^2 = p0^2 (1 - r^2 / a^2) is linear in r^2 (Johnson 1985, eq. 4.23); near any
    smooth contact edge p ~ sqrt(a - r), so p^2 is locally linear in r (and in r^2) there too.
    Fit a line to (r^2, p^2) over the ``n_fit`` contact nodes that precede the outermost
    ``n_skip`` ones (whose pressure is polluted by the element cut at the edge), take its zero,
    and clamp it to [r of the outermost contact node - its spacing, r of the first open node].
    Falls back to the outermost contact node when the contact has too few nodes.
    """
    r, pressure, active = np.asarray(r), np.asarray(pressure), np.asarray(active, dtype=bool)
    idx = np.flatnonzero(active)
    if idx.size == 0:
        return 0.0
    last = idx[-1]
    fit = idx[:-n_skip][-n_fit:] if idx.size > n_skip else idx[:0]
    fit = fit[r[fit] > 0]
    if fit.size < 3:
        return float(r[last])
    slope, intercept = np.polyfit(r[fit] ** 2, pressure[fit] ** 2, 1)
    if not (slope < 0 and intercept > 0):
        return float(r[last])
    lower = r[last] - (r[last] - r[idx[-2]] if idx.size > 1 else 0.0)
    upper = r[last + 1] if last + 1 < r.size else r[last]
    return float(np.clip(np.sqrt(-intercept / slope), lower, upper))


def lumped_contact_pressure(reaction, active, weight, r):
    """Nodal contact pressure [Pa] from the nodal contact reactions [N] (lumped recovery).

    p_i = lambda_i / int_S N_i 2 pi r ds: local, no oscillation at the contact edge (the
    consistent recovery M_AA p_A = lambda_A, tried first, rings near the edge, by 5 % of p0
    on the outermost nodes). At the pole the P2 vertex weight int N_pole 2 pi r ds is zero,
    so p(0) is extrapolated from the next three nodes as p = c0 + c2 r^2 (p is even in r).
    ``weight`` = int_S N_i 2 pi r ds [m^2] and ``r`` [m] per contact candidate node (sorted by r).
    """
    pressure = np.zeros(reaction.size)
    usable = active & (weight > 1e-9 * weight.max())  # the pole's weight is round-off
    pressure[usable] = reaction[usable] / weight[usable]
    if active[0] and not usable[0]:
        nearest = np.flatnonzero(usable)[:3]
        if nearest.size >= 2:
            c2, c0 = np.polyfit(r[nearest] ** 2, pressure[nearest], 1)
            pressure[0] = c0
        elif nearest.size == 1:
            pressure[0] = pressure[nearest[0]]
    return pressure
