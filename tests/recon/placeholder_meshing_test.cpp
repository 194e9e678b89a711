// Replaced by the meshing tests.
