"""Meshes: gmsh builds the axisymmetric r-z section of the hemisphere, refined at the contact."""
