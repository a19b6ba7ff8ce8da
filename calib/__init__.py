"""Finite-element calibration of the Vu-Quoc & Zhang (1999) elastoplastic normal contact law.

Pipeline (each stage a subpackage; imports run one way, left to right):

    meshes (gmsh hemisphere) -> calib.fe (axisymmetric FE: contact, plasticity, load paths)
    -> calib.fit (Ca, Kc by least squares; the one calibration recipe; the master table)
    -> calib.sweep (resumable keyed runs) -> calib.studies (Hertz limit, stability, mesh ladders)
    -> calib.report (result folders) -> calib.scenes (scene files, parameter tables)
    -> calib.commands + calib.cli (``nfdcal``)

calib.output writes every result file (atomically, stamped with commit, mesh and wall time).
The runtime law itself is ``nfdmodel`` (numpy/scipy only). Importing this package is light: the
FE stack (scikit-fem, gmsh, meshio, matplotlib) is imported only by the modules that need it.
"""
