// Grid transfers of the multigrid hierarchy and the banded solve.
#pragma once

#include <vector>

#include "recon/active_nodes.h"
#include "recon/grid.h"

namespace hos::recon {

// Restriction (full weighting, the transpose of prolongation divided by 8) and
// trilinear prolongation between a grid and its coarsened grid. The raw-array
// versions take each array in the layout of its grid's nodes and write only
// the active nodes of the output (restriction: coarse_active, prolongation:
// fine_active), so a banded hierarchy keeps zeros outside its bands and the
// pair stays transposed. Values that the input's layout does not store are zero.
void restrict_to_coarse(const GridGeometry& fine,
                        const std::vector<double>& r,
                        const GridGeometry& coarse,
                        std::vector<double>& rc);
void prolongate_add(const GridGeometry& coarse,
                    const std::vector<double>& ec,
                    const GridGeometry& fine,
                    std::vector<double>& x);
template <typename T>
void restrict_to_coarse(const GridGeometry& fine,
                        const ActiveNodes& fine_nodes,
                        const T* r,
                        const GridGeometry& coarse,
                        const ActiveNodes& coarse_active,
                        T* rc);
template <typename T>
void prolongate_add(const GridGeometry& coarse,
                    const ActiveNodes& coarse_nodes,
                    const T* ec,
                    const GridGeometry& fine,
                    const ActiveNodes& fine_active,
                    T* x);
// The same from a coarse layout to every node a fine layout stores (its
// active nodes and halo): starts a banded solve without a grid-sized array.
// The coarse layout must store every coarse node the fine nodes read.
void prolongate_add_to_stored(const GridGeometry& coarse,
                              const ActiveNodes& coarse_nodes,
                              const double* ec,
                              const ActiveNodes& fine_nodes,
                              double* x);

}  // namespace hos::recon
