// Replaced by the meshing sources.
