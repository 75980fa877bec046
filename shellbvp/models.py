"""Names of the reduced models and materials (a light module: no sympy, no JAX).

``plane_strain``: rho1 = 1, rho2 = 0; ``relaxed``: rho1, rho2 minimising the stretching
and bending energies (paper Sections 2-4). Materials: ``cg`` (compressible
Ciarlet-Geymonat, parameter lam = lambda*/mu*), ``nh`` (incompressible neo-Hookean) and
``koiter`` (the morphoelastic Koiter reference shell, Poisson ratio nu).
"""

MODELS = ("plane_strain", "relaxed")
MATERIALS = ("cg", "nh", "koiter")
#: the name of each material's parameter (None: the material has none)
MATERIAL_PARAMETER = {"cg": "lam", "nh": None, "koiter": "nu"}

__all__ = ["MODELS", "MATERIALS", "MATERIAL_PARAMETER", "material_parameter"]


def material_parameter(material: str, lam: float, nu: float) -> float:
    """The one material slot of the compiled functions: lam for cg, nu for koiter (lam, unused,
    for nh)."""
    return nu if MATERIAL_PARAMETER[material] == "nu" else lam
