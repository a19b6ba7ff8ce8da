"""Finite-element calibration of the Vu-Quoc & Zhang (1999) elastoplastic normal contact law.

Pipeline (each stage a subpackage; a stage imports only those before it, tests/test_layers.py):

    meshes (gmsh hemisphere), calib.output, calib.optional, calib.lammps_plugin
    -> calib.fe (axisymmetric FE: contact, plasticity, load paths), calib.sweep (resumable keyed runs)
    -> calib.fit (Ca, Kc by least squares; the one calibration recipe; the master table)
    -> calib.report (result folders) -> calib.studies (Hertz limit, stability, mesh ladders, impacts)
    -> calib.scenes (scene files, parameter tables) -> calib.commands -> calib.cli (``nfdcal``)

calib.output writes every result file (atomically, stamped with commit, mesh and wall time).
The runtime law itself is ``nfdmodel`` (numpy/scipy only). Importing this package is light: the
FE stack (scikit-fem, gmsh, meshio, matplotlib) is imported only by the modules that need it.
"""
