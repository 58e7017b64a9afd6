// Minimum-cost linear assignment of the rows of a cost matrix to distinct
// columns (Hungarian method with potentials, Kuhn-Munkres), used by CLEAR to
// give each observation of a view its own universe object.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

// `cost` is rows x cols with rows <= cols and finite entries. Returns, per
// row, the column assigned to it; the columns are distinct and the sum of
// the chosen costs is minimal. O(rows^2 * cols). Throws when rows > cols.
std::vector<int> SolveLinearAssignment(const Eigen::MatrixXd& cost);

}  // namespace colmap_lidar
