"""The paper's scenes, each a methods section in code (installed as ``shellbvp.problems``).

* :mod:`.cap_eversion`: everting spherical caps that snap (Section 5.2);
* :mod:`.closed_sphere`: homogeneous radius change of a closed sphere (Section 5.3).

A scene is data (geometry, stimulus, material, boundary conditions) handed to the public
``shellbvp`` API; it adds no solver of its own.
"""
