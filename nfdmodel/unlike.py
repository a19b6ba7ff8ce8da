"""The vz law of a contact of unlike bodies: the substitution, or the constants calibrated for the pair.

A contact of two bodies takes E* of the two in series and R* (``ContactPair.sphere_sphere``,
``ContactPair.sphere_wall``; Johnson 1985 section 4.2), exact while both are elastic, and its
yield point from the body with the lower p_Y = A_Y(nu) sigma_Y:

    P_Y = pi^3 R*^2 p_Y^3 / (6 E*^2) [N],   a_Y = (3 P_Y R* / (4 E*))^(1/3) [m]

Its plastic constants, Ca = Ca_hat a_Y / P_Y [m/N], Kc = Kc_hat / P_Y [1/N], and its window
(Vu-Quoc & Zhang 1999 eqs. 2.5, 3.6), come from

- the substitution: the dimensionless constants of the body that yields first (a tie: body i),
  each from a calibration of that body's material on a rigid flat; exact in the Hertz regime and
  unverified once a body yields on a compliant partner (Mesarovic & Fleck 2000);
- or the constants calibrated for that pair (``nfdcal calibrate --counter-E ...``: the sphere on
  its counter-body, whose parameter file states Ca_hat, Kc_hat relative to the pair's P_Y, a_Y),
  in place of the substitution's, with the same E*, R* and yield point.

An elastic wall (``sphere_wall_params``) never yields, so its contact's yield point is the
sphere's; constants calibrated on a flat that yielded first (``VZConstants.of`` keeps the yielding
body's sigma_y, nu: a lower A_Y(nu) sigma_y than the sphere's) are relative to the flat's P_Y and
are refused, as ``nfdcal export lammps`` and the plugin's ``pair_constants`` refuse them.

The LAMMPS plugin does the same: ``pair_coeff I J Ca_hat Kc_hat [window W]`` and a wall fix's
``pair_constants`` (nfdmodel/lammps/README.md, Mixing). The dimensionless constants of a pair hold
for its two materials at any size; the ratio of the radii is the calibration's (a wall: a flat).
"""
from __future__ import annotations

from dataclasses import dataclass

from .limits import NU_MAX
from .materials import ContactPair, Material, first_to_yield, yield_pressure
from .vz import CA_HAT_RANGE, KC_HAT_MAX, VZParams
from .validation import check_real
from .window import CalibrationWindow


@dataclass(frozen=True)
class VZConstants:
    """The dimensionless vz constants of a material (on a rigid flat) or of a calibrated pair:
    Ca_hat = Ca P_Y / a_Y [-] in [1e-8, 1e4], Kc_hat = Kc P_Y [-] in [0, 1e4] (nfd_limits.h), the
    window (None: not stated, nothing is flagged), yielding: (sigma_y [Pa], nu) of the body that
    yielded first in the calibration (None: not stated)."""

    Ca_hat: float
    Kc_hat: float
    window: CalibrationWindow | None = None
    yielding: tuple[float, float] | None = None

    def __post_init__(self):
        object.__setattr__(self, "Ca_hat", check_real("Ca_hat", self.Ca_hat, low=CA_HAT_RANGE[0], low_inclusive=True,
                                                      high=CA_HAT_RANGE[1], high_inclusive=True))
        object.__setattr__(self, "Kc_hat", check_real("Kc_hat", self.Kc_hat, low=0.0, low_inclusive=True,
                                                      high=KC_HAT_MAX, high_inclusive=True))
        if self.window is not None and not isinstance(self.window, CalibrationWindow):
            raise ValueError(f"window must be a CalibrationWindow or None, got {type(self.window).__name__}")
        if self.yielding is not None:
            if not isinstance(self.yielding, tuple) or len(self.yielding) != 2:
                raise ValueError(f"yielding must be (sigma_y [Pa], nu) or None, got {self.yielding!r}")
            sigma_y, nu = self.yielding
            object.__setattr__(self, "yielding", (check_real("yielding sigma_y", sigma_y, low=0.0, unit="Pa"),
                                                  check_real("yielding nu", nu, low=0.0, low_inclusive=True,
                                                             high=NU_MAX)))

    @classmethod
    def of(cls, params: VZParams) -> "VZConstants":
        """The dimensionless constants, window and yielding body of ``params`` (a parameter file's: a
        material's on a rigid flat, or a pair's, load_parameters of a counter-body file). A file of
        the vz-table law (nfdcal calibrate's default) has no two constants: refused, naming the law
        that file is and the calibration that writes the two (``--ship radius``)."""
        if type(params).__name__ == "VZTableParams":
            raise ValueError("params out of range: VZConstants.of takes the vz law's two constants, and this is the "
                             "vz-table law (nfdcal calibrate's default); load_parameters of a pair's file gives that "
                             "pair's law itself, or calibrate with --ship radius (or force) for a file of the two "
                             "constants")
        if not isinstance(params, VZParams):
            raise ValueError(f"params must be VZParams, got {type(params).__name__}")
        return cls(params.Ca_hat, params.Kc_hat, params.window, (params.pair.sigma_y, params.pair.nu))

    def params(self, pair: ContactPair) -> VZParams:
        """The vz law of ``pair``: Ca = Ca_hat a_Y / P_Y, Kc = Kc_hat / P_Y with the pair's P_Y, a_Y."""
        return VZParams.from_dimensionless(pair, self.Ca_hat, self.Kc_hat, self.window)


def _constants(name: str, value) -> VZConstants:
    if not isinstance(value, VZConstants):
        raise ValueError(f"{name} must be VZConstants, got {type(value).__name__}")
    return value


def sphere_sphere_params(material_i: Material, R_i: float, constants_i: VZConstants, material_j: Material,
                         R_j: float, constants_j: VZConstants, pair: VZConstants | None = None) -> VZParams:
    """The vz law of spheres i and j (radii [m]; ContactPair.sphere_sphere): the constants calibrated
    for the pair when given, else those of the body with the lower A_Y(nu) sigma_y (a tie: i)."""
    constants_i, constants_j = _constants("constants_i", constants_i), _constants("constants_j", constants_j)
    contact = ContactPair.sphere_sphere(material_i, R_i, material_j, R_j)
    if pair is not None:
        return _constants("pair", pair).params(contact)
    first = first_to_yield((material_i.sigma_y, material_i.nu), (material_j.sigma_y, material_j.nu))
    return (constants_i, constants_j)[first].params(contact)


def sphere_wall_params(material: Material, R: float, constants: VZConstants, E_wall: float, nu_wall: float,
                       pair: VZConstants | None = None) -> VZParams:
    """The vz law of a sphere (radius R [m]) on an elastic flat wall of E_wall [Pa], nu_wall
    (ContactPair.sphere_wall: first yield in the sphere): the constants calibrated for the sphere on
    that wall when given, else the sphere's. Pair constants whose calibration yielded first in the
    flat (their p_Y below the sphere's) are refused (module doc)."""
    constants = _constants("constants", constants)
    contact = ContactPair.sphere_wall(material, R, E_wall, nu_wall)
    if pair is None:
        return constants.params(contact)
    pair = _constants("pair", pair)
    if pair.yielding is not None and first_to_yield((contact.sigma_y, contact.nu), pair.yielding) == 1:
        raise ValueError(f"pair out of range: its constants were calibrated with first yield in the flat (p_Y = "
                         f"{yield_pressure(*pair.yielding):.4g} Pa, below the sphere's A_Y(nu) sigma_y = {contact.p_Y:.4g} Pa), relative "
                         f"to the flat's P_Y; an elastic wall yields in the sphere (P_Y = {contact.P_Y:.4g} N): "
                         f"nfdmodel.load_parameters of its file gives the pair's law")
    return pair.params(contact)
