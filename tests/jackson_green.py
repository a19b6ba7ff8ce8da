"""Jackson & Green (2005): the loading force of an elastic-perfectly plastic hemisphere pressed by a rigid
flat, their FE fit, a published reference the tests hold the FE and the vz master table against (not a
law of the package)."""
from __future__ import annotations

import numpy as np

from nfdmodel.materials import plane_strain_modulus


def jackson_green_force(w, E: float, nu: float, sigma_y: float, R: float):
    """The loading force P [N] at the interference w [m] of a hemisphere of radius R [m], Young's
    modulus E [Pa], Poisson's ratio nu and yield stress sigma_y [Pa] on a rigid flat (Jackson & Green
    2005, J. Tribol. 127, 343, eqs. 6, 8, 13-19):

        C = 1.295 exp(0.736 nu),  w_c = (pi C S_y / (2 E'))^2 R,  P_c = 4/3 (R / E')^2 (C pi S_y / 2)^3
        w / w_c <= 1.9:  P / P_c = (w / w_c)^(3/2)
        w / w_c > 1.9:   P / P_c = exp(-1/4 (w/w_c)^(5/12)) (w/w_c)^(3/2)
                                  + 4 H_G / (C S_y) [1 - exp(-1/25 (w/w_c)^(5/9))] (w/w_c)
        H_G / S_y = 2.84 [1 - exp(-0.82 (a/R)^(-0.7))],  a = sqrt(R w (w / (1.9 w_c))^B),
        B = 0.14 exp(23 S_y / E'),  E' = E / (1 - nu^2)

    fitted by them to w / w_c <= 110."""
    E_prime = plane_strain_modulus(E, nu)
    C = 1.295 * np.exp(0.736 * nu)
    w_c = (np.pi * C * sigma_y / (2.0 * E_prime)) ** 2 * R
    P_c = 4.0 / 3.0 * (R / E_prime) ** 2 * (C * np.pi * sigma_y / 2.0) ** 3
    x = np.asarray(w) / w_c
    B = 0.14 * np.exp(23.0 * sigma_y / E_prime)
    a = np.sqrt(R * np.asarray(w) * (x / 1.9) ** B)
    H_G = 2.84 * sigma_y * (1.0 - np.exp(-0.82 * (a / R) ** -0.7))
    plastic = (np.exp(-0.25 * x ** (5.0 / 12.0)) * x ** 1.5
               + 4.0 * H_G / (C * sigma_y) * (1.0 - np.exp(-x ** (5.0 / 9.0) / 25.0)) * x)
    return P_c * np.where(x <= 1.9, x ** 1.5, plastic)


def critical_interference(E: float, nu: float, sigma_y: float, R: float) -> float:
    """w_c [m] of Jackson & Green (2005): (pi C S_y / (2 E'))^2 R, C = 1.295 exp(0.736 nu)."""
    C = 1.295 * np.exp(0.736 * nu)
    return float((np.pi * C * sigma_y / (2.0 * plane_strain_modulus(E, nu))) ** 2 * R)
