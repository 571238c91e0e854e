"""Physical parameters of a soap-film flow, SI units, each default with its source.

References (keys used in the docstrings)
----------------------------------------
* [Huang2020] W. Huang, J. Iseringhausen, T. Kneiphof, Z. Qu, C. Jiang, M. B. Hullin,
  "Chemomechanical simulation of soap film flow on spherical bubbles", ACM TOG 39(4), 2020,
  doi:10.1145/3386569.3392094; public code github.com/RiverIntheSky/SoapBubble
  (``include/header.cuh`` for the constants, ``config.txt`` for the run configuration,
  ``kernel/bubble.cu`` for the dimensionless groups), all at commit a1eeee6 ("Modifications
  for publication", the repository's last): radius 0.05 m, H = 1 µm, Gammam 1e-6 mol m⁻²,
  ρ = 1000 kg m⁻³, evaporation 3e-8 m s⁻¹.  Its earlier commits 40b78f1 and c772208 had
  radius 0.04 m, Gammam 1.5e-7, ρ = 997 and evaporation 8e-8 and 8e-9; the 4 cm radius here is
  that of those commits, the other constants the publication's.
* [IAPWS2008] IAPWS, Release on the IAPWS Formulation 2008 for the viscosity of ordinary water
  substance: 1.0016 mPa s at 20 °C, 0.1 MPa.
* [CODATA2014] P. J. Mohr et al., CODATA recommended values 2014: R = 8.3144598 J mol⁻¹ K⁻¹.
* [CGPM1901] standard acceleration of gravity 9.80665 m s⁻².
* [SchwartzRoy1999] L. W. Schwartz, R. V. Roy, "Modeling draining flow in mobile and immobile
  soap films", J. Colloid Interface Sci. 218, 309-323 (1999): the lubrication flux
  :math:`\\rho g h^3/(12\\mu)` of a film between two immobile (no-slip) surfaces.
"""

import dataclasses
import math
from dataclasses import dataclass

from .limits import PARAMETER_LIMITS, check_number

__all__ = ["FilmParameters", "GAS_CONSTANT"]

#: molar gas constant R_g in J mol⁻¹ K⁻¹ [CODATA2014], the value [Huang2020] use
GAS_CONSTANT = 8.3144598

# boundary-layer air drag of [Huang2020] (kernel/bubble.cu: Cr = rho_a sqrt(nu_a R / U) / (rho H)):
AIR_DENSITY = 1.184  # kg m^-3, [Huang2020] include/header.cuh (air at 25 °C)
AIR_KINEMATIC_VISCOSITY = 1.562e-5  # m^2 s^-1, [Huang2020] include/header.cuh
AIR_DRAG_VELOCITY = 1.0  # m s^-1, the velocity scale U of [Huang2020] config.txt


@dataclass(frozen=True)
class FilmParameters:
    """Parameters of both film-flow models (SI units); frozen, validated on creation.

    Fields
    ------
    radius : bubble radius R in m.  Default 0.04 m, the radius of [Huang2020]'s
        commits 40b78f1 and c772208 (the released ``config.txt`` has 0.05 m).
    h0 : mean initial film thickness :math:`h_0` in m.  Default 2e-6 m: twice the
        half-thickness H = 1 µm of [Huang2020] ``config.txt``.
    viscosity : dynamic viscosity μ of the film liquid in Pa s, used by the rigid-interface
        model.  Default 1.0016e-3 Pa s, water at 20 °C [IAPWS2008].
    density : liquid density ρ in kg m⁻³.  Default 1000 [Huang2020] (header.cuh).
    surface_tension : surface tension of the clean liquid :math:`\\sigma_w` in N m⁻¹.  Default
        0.07275 N m⁻¹, water [Huang2020] (header.cuh).  Only the bound
        :math:`\\Gamma < \\sigma_w/(R_g T)` (σ > 0) uses it; the Marangoni force needs only ∇σ.
    gravity : g in m s⁻².  Default 9.80665 [CGPM1901] ([Huang2020] use 9.8).
    temperature : T in K, in the surfactant equation of state :math:`\\sigma = \\sigma_w -
        R_g T\\Gamma` ([Huang2020], the dilute limit).  Default 298.15 K [Huang2020] config.txt.
    surfactant : surface concentration :math:`\\Gamma_0` (mol m⁻², each surface) that goes with
        the thickness h0; the initial :math:`\\Gamma = \\Gamma_0 h/h_0` (perturbed, see
        *perturbation*).  Must be below :math:`\\sigma_w/(2R_gT(1+\\varepsilon))` (1.4e-5 mol m⁻² for the defaults),
        so that σ stays positive even where the film's surfactant is compressed two-fold.  Default 1e-6 mol m⁻², ``Gammam`` of [Huang2020] config.txt.  The
        Gibbs elasticity of the film is :math:`E_G = 2R_gT\\Gamma` (≈ 5 mN m⁻¹ here).
    air_drag : drag coefficient :math:`C_a` of the air on both sides of the film, in
        kg m⁻² s⁻¹ (force per area per velocity), plug-flow model only.  ``None`` (default):
        [Huang2020]'s laminar boundary-layer estimate
        :math:`C_a = 2\\rho_a\\sqrt{\\nu_a U/R}` with ρ_a = 1.184 kg m⁻³,
        ν_a = 1.562e-5 m² s⁻¹, U = 1 m s⁻¹ (their Cr, made dimensional; 0.0468 at R = 4 cm).
    evaporation : evaporation rate E in m s⁻¹ (thinning speed; water leaves, surfactant stays).
        Default 3e-8 m s⁻¹, ``evaporation`` of [Huang2020] header.cuh.  0 switches it off.
    perturbation : relative amplitude ε of the seeded smooth initial perturbation of h (and,
        for plug flow, of Γ/h), in [0, 0.5).  Default 0.05: a choice, not from a source.

    Every field is limited to a physical range (:data:`bubbleoptics.filmflow.limits.PARAMETER_LIMITS`,
    the reasons in :mod:`bubbleoptics.filmflow.limits`); a value outside it raises ``ValueError``
    naming the field, its unit and the range.

    >>> p = FilmParameters()
    >>> round(p.drag, 4), round(p.gibbs_elasticity * 1e3, 2)  # kg m^-2 s^-1, mN/m
    (0.0468, 4.96)
    >>> FilmParameters(h0=-1.0)
    Traceback (most recent call last):
    ...
    ValueError: h0 must be a finite number in [1e-09, 0.001] m (got -1.0)
    """

    radius: float = 0.04
    h0: float = 2e-6
    viscosity: float = 1.0016e-3
    density: float = 1000.0
    surface_tension: float = 0.07275
    gravity: float = 9.80665
    temperature: float = 298.15
    surfactant: float = 1e-6
    air_drag: float | None = None
    evaporation: float = 3e-8
    perturbation: float = 0.05

    def __post_init__(self):
        for name in PARAMETER_LIMITS:
            if name == "air_drag" and self.air_drag is None:
                continue
            object.__setattr__(self, name, check_number(name, getattr(self, name), PARAMETER_LIMITS))
        if self.surfactant * (1 + self.perturbation) * 2 >= self.surface_tension / (GAS_CONSTANT * self.temperature):
            raise ValueError(
                f"surfactant must be < sigma_w / (2 R_g T (1 + perturbation)) = "
                f"{self.surface_tension / (2 * GAS_CONSTANT * self.temperature * (1 + self.perturbation)):.4g} "
                f"mol m^-2 so that the surface tension stays positive (got {self.surfactant!r})")

    @property
    def drag(self):
        """The air-drag coefficient :math:`C_a` in kg m⁻² s⁻¹ (*air_drag*, or [Huang2020]'s estimate)."""
        if self.air_drag is not None:
            return self.air_drag
        return 2 * AIR_DENSITY * math.sqrt(AIR_KINEMATIC_VISCOSITY * AIR_DRAG_VELOCITY / self.radius)

    @property
    def gibbs_elasticity(self):
        """Gibbs elasticity of the film at :math:`\\Gamma_0`, :math:`E_G = 2R_gT\\Gamma_0` in N m⁻¹."""
        return 2 * GAS_CONSTANT * self.temperature * self.surfactant

    @property
    def drainage_time(self):
        """τ = 3μR / (ρ g h0²) in s: the time scale of the rigid-interface apex law (see
        :class:`~bubbleoptics.filmflow.RigidDrainage`)."""
        if self.gravity == 0:
            return math.inf
        return 3 * self.viscosity * self.radius / (self.density * self.gravity * self.h0**2)

    @property
    def equilibrium_exponent(self):
        """a = ρ g R h0 / (2 R_g T Γ0): the exponent of the plug-flow equilibrium
        :math:`h \\propto e^{-a\\cos\\theta}` (see :class:`~bubbleoptics.filmflow.PlugFlow`)."""
        return self.density * self.gravity * self.radius * self.h0 / (2 * GAS_CONSTANT * self.temperature * self.surfactant)

    def replace(self, **changes):
        """A copy with *changes* (validated again)."""
        return dataclasses.replace(self, **changes)

    def to_dict(self):
        """The fields as a plain dict (for a series' ``parameters``), with the resolved drag."""
        d = dataclasses.asdict(self)
        d["drag"] = self.drag
        return d
