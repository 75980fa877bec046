"""The paper's scenes, each a methods section in code (installed as ``shellbvp.problems``).

* :mod:`.cap_eversion`: everting spherical caps that snap (Section 5.2);
* :mod:`.closed_sphere`: homogeneous radius change of a closed sphere (Section 5.3);
* :mod:`.budding`: budding of a clamped cap under a localized stimulus (Section 5.4);
* :mod:`.pressure_cap`: clamped caps under external pressure, the classical snap-through
  benchmark (Budiansky 1959; Teng & Rotter 1989), beyond the paper;
* :mod:`.volvox` and :mod:`.pleodorina`: the cell sheets that motivate the paper, a
  spherical embryo whose bend region and contracting posterior start its inversion, and a
  bowl turned inside out by a travelling wave of cell wedging (docs: Cell sheets);
* :mod:`.thin_shells`: thin shells against their classical closed forms (Reissner's
  point-loaded sphere, a long cylinder's edge zone, Kirchhoff's plates) at any R/t.

A scene is data (geometry, stimulus, material, boundary conditions) handed to the public
``shellbvp`` API; it adds no solver of its own.
"""
