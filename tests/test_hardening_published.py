"""The FE press of a linearly hardening sphere against a published FE fit of the same problem:
Ghaednia, Brake, Berryhill & Jackson (2019), "Strain hardening from elastic-perfectly plastic to
perfectly elastic flattening single asperity contact", J. Tribol. (their FE of a hemisphere with
bilinear hardening, tangent modulus E_t, flattened by a flat, fitted in closed form).

The source read is not the paper itself (not reachable here) but the transcription of its equations
and of its figures' parameters by the group of one of its authors (M. R. W. Brake, Rice University):
repository tmd-lab/microslip-rough-contact at commit 21706045ee270bdd3ca861e4a3b7ba367aed59e5, files
ROUTINES/FRIC_MODELS/PLASTIC/GHAEDNIA_ET_AL_FLATTENING.m (the equations, numbered as in the paper)
and TESTS/verification_normal_plasticity.m (the parameters of the paper's Figs. 8-12, which that
script redraws to check the transcription); eq. 30 reads the same, 3.3 included, in the group's
tmd-lab/tmdsimpy (tmdsimpy/jax/nlforces/roughcontact/_asperity_functions.py). What is used here:

    E = ((1 - nu_s^2) / E_s + (1 - nu_f^2) / E_f)^-1                          (eq. 3)
    C = 1.295 exp(0.736 nu_s),  delta_c = (pi C S_y / (2 E))^2 R              (eqs. 5, 6)
    F_e = 4/3 E sqrt(R) Delta^(3/2)                   (Hertz: eq. 31 less a factor pi the transcription drops)
    Delta <= 1.9 delta_c: F = F_e, whatever E_t                               (sec. 3.2)
    Delta >  1.9 delta_c: F = F_p + (F_e - F_p) (1 - exp(-3.3 E_t / E_s))     (eq. 30)

with F_p the elastic-perfectly plastic force of Jackson & Green (eqs. 27-29: F_c = 4/3 (R/E)^2
(C pi S_y / 2)^3; F_p / F_c = exp(-(Delta/delta_c)^(5/12) / 4) (Delta/delta_c)^(3/2) + 4 (H/S_y) / C
[1 - exp(-(Delta/delta_c)^(5/9) / 25)] Delta/delta_c, H/S_y = 2.84 - 0.92 [1 - cos(pi a / R)]) and a
the model's contact radius (eqs. 23-26; eq. 26 as the transcription corrects it, noting the printed
one is wrong). E_t, "the tangent modulus" in both transcriptions, is taken as the slope of the
uniaxial stress against the TOTAL strain after yield, as the title's "to perfectly elastic" at E_t =
E_s implies; the FE's plastic modulus is then H = E_s E_t / (E_s - E_t) (calib.fe.flow_curve).

The published case is the paper's Fig. 11: an aluminium-like hemisphere E_s = 71 GPa, nu_s = 0.33,
S_y = 500 MPa, E_t = 0.1 E_s, R = 1 mm, on an elastic flat E_f = 200 GPa, nu_f = 0.3, to Delta / R =
0.05 (Delta / delta_c = 102, a / R 0.3). Here: the pair press (calib.fe.two_body, the flat a condensed
elastic block), finite strain (a / R reaches 0.3), a coarse mesh (R / 50 elements at the contact: 1.4 to
16 across it), displacement control, and the same sphere with E_t = 0.02 E_s (the value of the paper's
Figs. 9 and 12) for the trend.
"""
import math

import numpy as np
import pytest

from calib.fe import ElasticMaterial, VonMisesMaterial
from calib.fe.flow_curve import LinearHardening
from calib.fe.loadpath import run_press
from calib.fe.two_body import TwoBodySolver
from calib.fe.von_mises import HardeningMaterial
from meshes.counter_body import BlockMeshSpec, pair_mesh
from meshes.hemisphere import HemisphereMeshSpec

R = 1e-3                                      # [m]
E_S, NU_S, S_Y = 71e9, 0.33, 500e6            # the sphere [Pa], [-], [Pa]
E_F, NU_F = 200e9, 0.3                        # the flat
TANGENTS = (0.02, 0.1)                        # E_t / E_s; 0.1 is the paper's Fig. 11
E_COMP = 1.0 / ((1 - NU_S ** 2) / E_S + (1 - NU_F ** 2) / E_F)          # eq. 3 [Pa]
C_NU = 1.295 * math.exp(0.736 * NU_S)
DELTA_C = (math.pi * C_NU * S_Y / (2 * E_COMP)) ** 2 * R                # eq. 5 [m]
# 1.5 delta_c (the published elastic range), then the paper's range Delta / R <= 0.05
APPROACHES = np.array([1.5 * DELTA_C / R, 0.002, 0.005, 0.01, 0.02, 0.035, 0.05]) * R


def hertz(delta):
    """F_e [N] at the interference ``delta`` [m] (Hertz; eq. 31 as transcribed)."""
    return 4.0 / 3.0 * E_COMP * math.sqrt(R) * delta ** 1.5


def ghaednia(delta, tangent):
    """(F, F_p) [N] of the published fit at the interference ``delta`` [m] and E_t / E_s = ``tangent``
    (module docstring: eqs. 23-30 as transcribed; F_p is the perfectly plastic part)."""
    F_e, x = hertz(delta), delta / DELTA_C
    if x <= 1.9:
        return F_e, F_e
    B = 0.14 * math.exp(23.0 * S_Y / E_COMP)                                              # eq. 24
    a_p = R * (math.pi * C_NU * S_Y / (2 * E_COMP)) * math.sqrt(x * (x / 1.9) ** B)     # eq. 23
    root = math.sqrt(E_S / S_Y)
    upsilon = (-2.0 * root * tangent ** (1.0 - (delta - DELTA_C) / R)
               / (4.0 - 3.0 * math.exp(-2.0 * root * tangent)) / (1.0 - tangent))          # eq. 26
    a = math.sqrt(R * delta) + (a_p - math.sqrt(R * delta)) * math.exp(upsilon)          # eq. 25
    H = 2.84 - 0.92 * (1.0 - math.cos(math.pi * a / R))                                   # eq. 28
    F_c = 4.0 / 3.0 * (R / E_COMP) ** 2 * (C_NU * math.pi * S_Y / 2.0) ** 3               # eq. 29
    F_p = F_c * (math.exp(-0.25 * x ** (5.0 / 12.0)) * x ** 1.5
                 + 4.0 * H / C_NU * (1.0 - math.exp(-x ** (5.0 / 9.0) / 25.0)) * x)        # eq. 27
    return F_p + (F_e - F_p) * (1.0 - math.exp(-3.3 * tangent)), F_p                       # eq. 30


@pytest.fixture(scope="module")
def presses(mesh_cache):
    """The FE forces [N] at APPROACHES: elastic, perfectly plastic ("perfect") and each E_t / E_s."""
    def spec(radius, kind=HemisphereMeshSpec):
        return kind(radius=radius, contact_size=R / 50, refined_radius=0.35 * R, refined_depth=0.2 * R,
                    far_size=radius / 6)

    mesh = pair_mesh(spec(R), spec(2 * R, BlockMeshSpec), cache_dir=mesh_cache)
    materials = {"elastic": ElasticMaterial(E_S, NU_S), "perfect": VonMisesMaterial(E_S, NU_S, S_Y)}
    for tangent in TANGENTS:
        materials[tangent] = HardeningMaterial(E_S, NU_S, LinearHardening(S_Y, E_S * tangent / (1 - tangent)))
    out = {}
    for name, material in materials.items():
        solver = TwoBodySolver(mesh, material, ElasticMaterial(E_F, NU_F), kinematics="finite-strain")
        out[name] = np.array([r.record.P for r in run_press(solver, APPROACHES)[0]])
    return out


def test_below_the_published_elastic_limit_hardening_changes_nothing(presses):
    """At 1.5 delta_c (published: F = F_e for Delta <= 1.9 delta_c, whatever E_t) the perfectly plastic
    and the two hardening spheres give one force, the elastic sphere's on the same mesh (measured: the
    three within 9e-4 of each other, 1.2-1.3 % below the elastic sphere: the first points have yielded).
    The elastic FE is there 4.1 % below Hertz's closed form: 1.4 elements across the contact."""
    first = np.array([presses["perfect"][0]] + [presses[t][0] for t in TANGENTS])
    assert np.ptp(first) / first.min() < 2e-3
    assert np.all(np.abs(first / presses["elastic"][0] - 1.0) < 0.02)


def test_the_published_fit_of_the_hardening_force(presses):
    """The force against eq. 30 over the paper's range Delta / R 0.002-0.05 (Delta / delta_c 4-102).

    Measured (FE / fit - 1 at Delta / R 0.002, 0.005, 0.01, 0.02, 0.035, 0.05): the perfectly plastic
    FE against the fit's perfectly plastic part F_p (Jackson & Green's, itself an FE fit) -0.7, +1.0,
    +0.3, -2.2, -2.2, -4.3 %; the hardening sphere against the fit F, E_t = 0.1 E_s (the paper's Fig.
    11) -1.9, -0.7, -3.1, -5.3, -6.9, -7.2 %, E_t = 0.02 E_s -1.0, +0.7, -1.8, -2.2, -3.3, -3.2 %. The
    bounds, -5 %..+2 % and -10 %..+3 %: the mesh (2-16 elements across the contact; its elastic press
    is 4 % below Hertz at 1.4 elements) and the perfectly plastic part, which alone parts by up to
    4.3 %; the hardening part of the FE is below the fit's (the next test), which adds up to -3 %."""
    for i, delta in enumerate(APPROACHES[1:], start=1):
        F_p = ghaednia(delta, TANGENTS[0])[1]
        assert -0.05 < presses["perfect"][i] / F_p - 1.0 < 0.02, (delta / R, presses["perfect"][i], F_p)
        for tangent in TANGENTS:
            F = ghaednia(delta, tangent)[0]
            assert -0.10 < presses[tangent][i] / F - 1.0 < 0.03, (tangent, delta / R, presses[tangent][i], F)


def test_the_hardening_weight_is_constant_but_below_the_published_one(presses):
    """Eq. 30 says the hardening sphere closes a fixed part w = 1 - exp(-3.3 E_t / E_s) of the gap from
    the perfectly plastic force to Hertz's, whatever the interference. The FE's w = (F - F_perfect) /
    (F_e - F_perfect), F_e Hertz's as in eq. 30, beyond the transition (Delta / delta_c >= 10):

    - for E_t = 0.1 E_s constant within the mesh, as published (measured 0.194-0.232, max / min 1.20);
      for 0.02 E_s the hardening adds 0.5-4 % to the force and the mesh's steps of the contact radius
      show (measured 0.012-0.058);
    - larger for the larger E_t at every interference;
    - below the published weight (0.281 and 0.064): 0.69-0.83 of it for 0.1 E_s (an exponent of
      2.2-2.6 against 3.3), 0.18-0.91 (mean 0.69) for 0.02 E_s. Against the elastic FE's force instead of
      Hertz's the exponent is 1.8-2.1 here, and 1.5-2.8 in coarse presses of the same sphere on the
      rigid flat (finite or small strain, E_t / E_s 0.02-0.8; one mesh-step outlier at 0.02 aside) and
      of the package's reference sphere (E / sigma_Y 700, E_t / E_s 0.02-0.1). A discrepancy between
      this FE and the published fit, recorded here, not explained: the force stays within -7.2 % of
      the fit (the previous test)."""
    beyond = APPROACHES / DELTA_C >= 10.0
    gap = np.array([hertz(d) for d in APPROACHES[beyond]]) - presses["perfect"][beyond]
    weights = {}
    for tangent in TANGENTS:
        w = (presses[tangent][beyond] - presses["perfect"][beyond]) / gap
        published = 1.0 - math.exp(-3.3 * tangent)
        print(f"E_t/E_s {tangent}: w {np.round(w, 4)}, published {published:.4f}, exponent "
              f"{np.round(-np.log(1.0 - w) / tangent, 2)}")
        assert np.all(w > 0) and np.all(w < published) and w.mean() > 0.5 * published
        weights[tangent] = w
    assert weights[0.1].max() / weights[0.1].min() < 1.3
    assert np.all(weights[0.1] > 0.6 * (1.0 - math.exp(-3.3 * 0.1)))
    assert np.all(weights[0.1] > weights[0.02])
