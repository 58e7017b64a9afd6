#include "src/matching/linear_assignment.h"

#include <limits>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

// The shortest augmenting path form of the Hungarian method: rows are added
// one at a time; for each, a Dijkstra-like search over columns with reduced
// costs cost(i, j) - u(i) - v(j) >= 0 finds the cheapest augmenting path,
// and the potentials are updated so that reduced costs stay non-negative.
std::vector<int> SolveLinearAssignment(const Eigen::MatrixXd& cost) {
  const int num_rows = static_cast<int>(cost.rows());
  const int num_cols = static_cast<int>(cost.cols());
  THROW_CHECK(num_rows <= num_cols, "Linear assignment of "
                                        << num_rows << " rows to " << num_cols
                                        << " columns");
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // 1-based with a virtual column 0 that holds the row being inserted.
  std::vector<double> u(num_rows + 1, 0.0);
  std::vector<double> v(num_cols + 1, 0.0);
  std::vector<int> row_of_col(num_cols + 1, 0);
  std::vector<int> way(num_cols + 1, 0);
  for (int row = 1; row <= num_rows; ++row) {
    row_of_col[0] = row;
    int col0 = 0;
    std::vector<double> min_to(num_cols + 1, kInf);
    std::vector<bool> used(num_cols + 1, false);
    do {
      used[col0] = true;
      const int row0 = row_of_col[col0];
      double delta = kInf;
      int col1 = 0;
      for (int col = 1; col <= num_cols; ++col) {
        if (used[col]) continue;
        const double reduced = cost(row0 - 1, col - 1) - u[row0] - v[col];
        if (reduced < min_to[col]) {
          min_to[col] = reduced;
          way[col] = col0;
        }
        if (min_to[col] < delta) {
          delta = min_to[col];
          col1 = col;
        }
      }
      THROW_CHECK(col1 != 0, "Linear assignment: non-finite cost");
      for (int col = 0; col <= num_cols; ++col) {
        if (used[col]) {
          u[row_of_col[col]] += delta;
          v[col] -= delta;
        } else {
          min_to[col] -= delta;
        }
      }
      col0 = col1;
    } while (row_of_col[col0] != 0);
    // Augment along the path back to the virtual column.
    do {
      const int col1 = way[col0];
      row_of_col[col0] = row_of_col[col1];
      col0 = col1;
    } while (col0 != 0);
  }
  std::vector<int> col_of_row(num_rows, -1);
  for (int col = 1; col <= num_cols; ++col) {
    if (row_of_col[col] != 0) {
      col_of_row[row_of_col[col] - 1] = col - 1;
    }
  }
  return col_of_row;
}

}  // namespace colmap_lidar
