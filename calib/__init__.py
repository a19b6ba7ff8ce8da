"""Finite-element calibration of the Vu-Quoc & Zhang (1999) normal contact law.

Pipeline: ``meshes`` (gmsh hemisphere) -> ``calib`` solve (axisymmetric FE, contact,
plasticity) -> ``calib`` fit (Ca, Kc) -> ``nfdmodel`` (runtime law) -> ``results/`` (report).

Importing this package is light: the FE stack (scikit-fem, gmsh, meshio, matplotlib) is
imported only by the modules that need it.
"""
