"""The reference case of Vu-Quoc & Zhang (1999), section 2, in one place.

An aluminium sphere of radius R = 0.1 m (E = 70 GPa, nu = 0.3, sigma_Y = 100 MPa, rho = 2699
kg/m^3, mass 11.306 kg) pressed on a rigid frictionless flat; load paths ABC, ADE, AFG to
P_max = 500, 1000, 1500 N. The paper's Abaqus calibration (2141 CAX6 elements) gives P_Y = 36.45 N,
Ca = 2.33e-7 m/N and Kc = 2.69e-4 1/N, alpha_max = 1.56e-5 m and e = 0.737 on path AFG.
Every default of the package that means "the paper's case" reads these constants.
"""
E = 70e9               # Young's modulus [Pa]
NU = 0.3               # Poisson's ratio [-]
SIGMA_Y = 100e6        # uniaxial yield stress [Pa]
RHO = 2699.0           # density [kg/m^3]
R = 0.1                # sphere radius [m]
PEAKS = (500.0, 1000.0, 1500.0)   # P_max of the paths ABC, ADE, AFG [N]
CA = 2.33e-7           # paper's plastic contact-radius rate [m/N]
KC = 2.69e-4           # paper's curvature-factor rate [1/N]
P_Y = 36.45            # paper's first-yield force [N] (its A_Y(0.3) rounded to 1.61)
ALPHA_MAX_AFG = 1.56e-5   # paper's approach at 1500 N [m]
E_AFG = 0.737          # paper's restitution of path AFG [-]


_SPHERE = (E, NU, R)


def is_reference_sphere(E: float, nu: float, radius: float, sigma_y: float | None = None) -> bool:
    """The paper's sphere: E [Pa], nu [-], R [m] and, if given, sigma_Y [Pa] of the reference case."""
    return (E, nu, radius) == _SPHERE and (sigma_y is None or sigma_y == SIGMA_Y)
