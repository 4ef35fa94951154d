// Stage 6 (§3.1): mean-shift clustering with the Epanechnikov kernel.
#pragma once

#include "kd_tree.h"

#include <Eigen/Core>
#include <functional>
#include <vector>

namespace symmetry {

struct Cluster {
    Eigen::VectorXd mode;      ///< the local maximum of the density
    std::vector<int> members;  ///< points within the bandwidth of the mode (a point may be in several)
    int height = 0;            ///< number of points within the bandwidth of the mode (the density at the mode)
};

struct MeanShiftOptions {
    double bandwidth = 0.05;  ///< h, in the units of the points
    int min_support = 5;      ///< clusters whose height is below this are not returned
    int max_iterations = 100;
    /// The densities that order the starting points are counted up to this many
    /// neighbours: beyond it every start is dense enough to climb early, and an uncapped
    /// count costs as much as the neighbourhood is large (on a torus, every point's).
    int density_cap = 256;
    /// Densities are counted by scanning the points in the cells of side h around each
    /// point, cells that divide this many coordinates (the translation's three first, then
    /// the rotation entries that vary most).  More axes, fewer points scanned but 3^axes
    /// cells looked up: on a facade's 128,000 improper votes, 3 axes scan a median of 1,340
    /// points, 4 axes 450; 5 axes were slower than 4 on the accuracy scenes.  The count is
    /// the same for any value of this and the next two; only the work differs.
    int grid_axes = 4;
    /// ...when the cells around a point hold at most this many points; the kd-tree counts
    /// the others (a crowded neighbourhood, whose count the tree stops at the cap after the
    /// nearest points).  Measured on one thread, densities of the first clustering against
    /// the tree alone: 2048 gave 0.9 s against 7.8 s on the facade, 0.7 against 2.1 on
    /// cad_joint, 0.9 against 0.9 on the cone; 1024 and 4096 did no better overall.  The
    /// same rule finds the points near removed votes (densities_after_removal).
    int max_scanned_neighbours = 2048;
    /// ...and when at least this share of the points is to be counted: the grid sorts all of
    /// them, which a recount around a few removed votes does not repay.
    double min_grid_share = 0.125;
    /// Stop after this many modes (0: no limit).  Ascents start from the densest points,
    /// so the modes found first are the high ones; a caller that can only use the top few
    /// need not climb every hill of the background noise.
    int max_modes = 0;
    /// An ascent that comes within this many bandwidths of a mode found before stops there:
    /// it is that mode's.  Within h/2 it would end there (modes closer than h/2 are merged);
    /// within h its votes are that mode's members, and verification takes two modes closer
    /// than h for one relation (it tries the higher only).  Measured on a coarse helmet
    /// (1,000 faces, 130,000 points in Γ): 95 % of the ascents join a known mode, after 8
    /// steps on average at h/2.
    double join_radius = 1.0;
    /// Ascents climbed at a time, on every core (see mean_shift()).  The result does not
    /// depend on it; the work does: an ascent whose start a path committed before it covers
    /// was climbed in vain.
    int batch_size = 4;
    /// Called on every updated estimate; lets the caller keep modes on a manifold
    /// (here: the rotation block on SO(3)).  May be empty.
    std::function<void(Eigen::Ref<Eigen::VectorXd>)> project;
};

/// The significant modes of ρ(T) = Σ K(||T − T_i|| / h).  For the Epanechnikov kernel the
/// mean-shift step is the plain mean of the points within h (its shadow is the flat
/// kernel, Comaniciu and Meer 2002), so every step is one kd-tree range query.  Starting
/// points are taken in decreasing order of density and skipped when they lie within h/2
/// of an earlier ascent path, which they would follow anyway (Comaniciu and Meer's basin
/// of attraction); modes closer than h/2 are merged.  Clusters are returned in
/// decreasing order of height; the result is deterministic, and the same at any thread count.
std::vector<Cluster> mean_shift(const KdTree& tree, const MeanShiftOptions& options);

/// The same, with the densities that order the starting points given (see densities()).
std::vector<Cluster> mean_shift(const KdTree& tree, const std::vector<int>& density, const MeanShiftOptions& options);

/// The density at every point of the tree: the points within h of it, counted up to
/// density_cap.  Most of the cost of mean shift on dense votes (a facade's 120 copies).
std::vector<int> densities(const KdTree& tree, const MeanShiftOptions& options);

/// The densities after some points were removed, without counting every point again:
/// `tree` holds the points that remain, point i being point earlier_index[i] of the tree
/// whose densities were `before`; `removed` holds the coordinates of the others.  Only the
/// points within h of a removed one are counted again, so the result equals densities(tree).
/// Those points are found in cells as the densities are (a torus whose rotational family
/// leaves Γ: 0.16 s against 1.7 s for a range query around each of its 61,000 votes).
std::vector<int> densities_after_removal(const KdTree& tree, const std::vector<int>& before,
                                         const std::vector<int>& earlier_index, const KdTree::Points& removed,
                                         const MeanShiftOptions& options);

}  // namespace symmetry
