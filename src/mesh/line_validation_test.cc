#include "src/mesh/line_validation.h"

#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Points on two half-planes meeting at the x axis, as a wall (z >= 0 on
// y = 0) on a floor (y >= 0 on z = 0): a concave crease along x, sampled
// every `spacing` metres with `noise` (std, metres) across each plane.
std::vector<Eigen::Vector3d> CornerPoints(double spacing, double noise,
                                          double angle_deg = 90.0) {
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, noise);
  const double angle = angle_deg * M_PI / 180.0;
  // The wall's direction in the y-z plane, at angle from the floor (+y).
  const Eigen::Vector3d wall_dir(0, std::cos(angle), std::sin(angle));
  const Eigen::Vector3d wall_normal(0, -std::sin(angle), std::cos(angle));
  std::vector<Eigen::Vector3d> points;
  for (double x = -2; x <= 2; x += spacing) {
    for (double u = spacing / 2; u <= 1.0; u += spacing) {
      points.emplace_back(x, u, gauss(rng));                    // floor
      points.push_back(Eigen::Vector3d(x, 0, 0) + u * wall_dir +
                       gauss(rng) * wall_normal);               // wall
    }
  }
  return points;
}

TEST(LineValidation, MovesASegmentOntoTheCreaseOfThePoints) {
  const std::vector<Eigen::Vector3d> points = CornerPoints(0.02, 0.002);
  const LineValidator validator(LineValidationOptions(), points);
  // Spacing: the 4th neighbour on a 2 cm grid is 2 cm away (the 4 edge
  // neighbours), up to the noise.
  EXPECT_NEAR(validator.spacing(), 0.02, 0.003);
  // 1.8 cm off the crease, slightly skewed: within max_offset_factor * s
  // (2.6 cm).
  const Eigen::Vector3d start(-1.0, 0.01, 0.015);
  const Eigen::Vector3d end(1.0, 0.015, 0.01);
  const ValidatedLine line = validator.Validate(start, end, 1);
  ASSERT_EQ(line.status, LineValidationStatus::kCrease)
      << LineValidationStatusName(line.status);
  // Moved by one shift across the segment: onto the crease at the
  // segment's middle, within a quarter of the spacing (the skew blurs the
  // section by 0.5 cm).
  const Eigen::Vector3d middle = 0.5 * (line.start + line.end);
  EXPECT_LT(std::hypot(middle.y(), middle.z()), 0.005);
  // Parallel to the crease, 1.5 cm off: onto it within the noise.
  const ValidatedLine parallel = validator.Validate(
      Eigen::Vector3d(-1, 0.015, 0.0), Eigen::Vector3d(1, 0.015, 0.0), 2);
  ASSERT_EQ(parallel.status, LineValidationStatus::kCrease);
  EXPECT_FALSE(parallel.with_side_face);
  EXPECT_LT(std::hypot(parallel.start.y(), parallel.start.z()), 0.002);
  EXPECT_NEAR(line.offset_m, std::hypot(0.0125, 0.0125), 0.003);
  EXPECT_NEAR((line.end - line.start).norm(), (end - start).norm(), 1e-12);
  // The faces leave the crease along the floor (+y) and up the wall (+z),
  // in either order, as unit vectors orthogonal to the segment.
  const auto& directions = parallel.face_directions;
  const bool floor_first = directions[0].y() > directions[1].y();
  EXPECT_LT((directions[floor_first ? 0 : 1] - Eigen::Vector3d::UnitY())
                .norm(), 0.02);
  EXPECT_LT((directions[floor_first ? 1 : 0] - Eigen::Vector3d::UnitZ())
                .norm(), 0.02);
  for (const Eigen::Vector3d& direction : line.face_directions) {
    EXPECT_NEAR(direction.norm(), 1.0, 1e-9);
    EXPECT_NEAR(direction.dot((line.end - line.start).normalized()), 0.0,
                1e-9);
  }
  // Deterministic for a seed.
  const ValidatedLine again = validator.Validate(start, end, 1);
  EXPECT_EQ(again.start, line.start);
}

TEST(LineValidation, AcceptsObtuseCreasesAndRejectsFlatOnes) {
  for (const double angle_deg : {45.0, 135.0}) {
    const std::vector<Eigen::Vector3d> points =
        CornerPoints(0.02, 0.002, angle_deg);
    const LineValidator validator(LineValidationOptions(), points);
    EXPECT_EQ(validator
                  .Validate(Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(1, 0, 0),
                            3)
                  .status,
              LineValidationStatus::kCrease)
        << angle_deg;
  }
  // 170 degrees between floor and wall: 10 degrees between the faces'
  // cross-sections, below min_crease_angle_deg.
  const std::vector<Eigen::Vector3d> flat = CornerPoints(0.02, 0.002, 170.0);
  const LineValidator validator(LineValidationOptions(), flat);
  const ValidatedLine line = validator.Validate(Eigen::Vector3d(-1, 0, 0),
                                                Eigen::Vector3d(1, 0, 0), 3);
  EXPECT_TRUE(line.status == LineValidationStatus::kParallelFaces ||
              line.status == LineValidationStatus::kOnePlane)
      << LineValidationStatusName(line.status);
  EXPECT_EQ(line.start, Eigen::Vector3d(-1, 0, 0));
}

TEST(LineValidation, LeavesOutSegmentsThatAreNotOnACrease) {
  const std::vector<Eigen::Vector3d> points = CornerPoints(0.02, 0.002);
  const LineValidator validator(LineValidationOptions(), points);
  // A texture line on the floor, 0.5 m from the crease: one face.
  EXPECT_EQ(validator
                .Validate(Eigen::Vector3d(-1, 0.5, 0),
                          Eigen::Vector3d(1, 0.5, 0), 1)
                .status,
            LineValidationStatus::kOnePlane);
  // Parallel to the crease but 5 cm off it in the open: the support sees
  // the corner farther than max_offset_factor * s (2.6 cm).
  const ValidatedLine off = validator.Validate(
      Eigen::Vector3d(-1, 0.05, 0.05), Eigen::Vector3d(1, 0.05, 0.05), 1);
  EXPECT_EQ(off.status, LineValidationStatus::kOffCrease)
      << LineValidationStatusName(off.status);
  EXPECT_NEAR(off.offset_m, std::hypot(0.05, 0.05), 0.005);
  // In empty space.
  EXPECT_EQ(validator
                .Validate(Eigen::Vector3d(-1, 3, 3), Eigen::Vector3d(1, 3, 3),
                          1)
                .status,
            LineValidationStatus::kFewPoints);
  // Two faces crossing (a plus-shaped section), not a corner.
  std::vector<Eigen::Vector3d> cross = points;
  for (const Eigen::Vector3d& p : points) cross.push_back(-p);
  const LineValidator cross_validator(LineValidationOptions(), cross);
  EXPECT_EQ(cross_validator
                .Validate(Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(1, 0, 0),
                          1)
                .status,
            LineValidationStatus::kNotACorner);
}

TEST(LineValidation, StepEdgeIsLeftOut) {
  // A 5 cm step: two parallel floors, the near one ending at y = 0.
  std::vector<Eigen::Vector3d> points;
  for (double x = -1; x <= 1; x += 0.02) {
    for (double y = 0.01; y <= 0.6; y += 0.02) {
      points.emplace_back(x, y, 0.05);
      points.emplace_back(x, -y, 0.0);
    }
  }
  const LineValidator validator(LineValidationOptions(), points);
  const ValidatedLine line = validator.Validate(
      Eigen::Vector3d(-0.8, 0, 0.05), Eigen::Vector3d(0.8, 0, 0.05), 1);
  EXPECT_EQ(line.status, LineValidationStatus::kParallelFaces)
      << LineValidationStatusName(line.status);
}

TEST(LineValidation, FindsTheCreaseOfAStepBesideItsParallelFaces) {
  // A 6 cm step sampled on its riser too, one point per 4 cm^2 drawn
  // uniformly (a grid would line up rows across the faces): the near floor
  // (z = 0.06, y > 0), the riser (y = 0) and the far floor (z = 0, y < 0).
  // Within the support of the step's top edge (5 s, about 11 cm) the two
  // floors hold more points than the riser, so the two largest faces are
  // parallel; the crease is between the near floor and the riser.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 3000; ++i) {
    points.emplace_back(-1 + 2 * uniform(rng), 0.6 * uniform(rng), 0.06);
    points.emplace_back(-1 + 2 * uniform(rng), -0.6 * uniform(rng), 0.0);
  }
  for (int i = 0; i < 300; ++i) {
    points.emplace_back(-1 + 2 * uniform(rng), 0.0, 0.06 * uniform(rng));
  }
  const Eigen::Vector3d start(-0.8, 0.005, 0.063);
  const Eigen::Vector3d end(0.8, 0.005, 0.063);
  LineValidationOptions two_faces;
  two_faces.max_faces = 2;
  EXPECT_EQ(LineValidator(two_faces, points).Validate(start, end, 1).status,
            LineValidationStatus::kParallelFaces);
  const LineValidator validator(LineValidationOptions(), points);
  const ValidatedLine line = validator.Validate(start, end, 1);
  ASSERT_EQ(line.status, LineValidationStatus::kCrease)
      << LineValidationStatusName(line.status);
  EXPECT_TRUE(line.with_side_face);
  // Onto the top edge (y = 0, z = 0.06), within a quarter of the spacing.
  EXPECT_LT(std::hypot(line.start.y(), line.start.z() - 0.06), 0.005);
  EXPECT_LT(std::hypot(line.end.y(), line.end.z() - 0.06), 0.005);
  // The faces leave it along the near floor (+y) and down the riser (-z).
  const auto& directions = line.face_directions;
  const bool floor_first = directions[0].y() > directions[1].y();
  EXPECT_LT((directions[floor_first ? 0 : 1] - Eigen::Vector3d::UnitY()).norm(),
            0.1);
  EXPECT_LT((directions[floor_first ? 1 : 0] + Eigen::Vector3d::UnitZ()).norm(),
            0.1);
  // A crease with the smaller face is kept only where the segment lies at
  // it already: 1.5 cm off the top edge (0.7 s) it is refused; the
  // largest faces' creases are accepted up to 1.3 s.
  EXPECT_EQ(validator
                .Validate(Eigen::Vector3d(-0.8, 0.015, 0.06),
                          Eigen::Vector3d(0.8, 0.015, 0.06), 1)
                .status,
            LineValidationStatus::kParallelFaces);
}

TEST(LineValidation, ThePlaneBandFollowsTheNoiseOfThePoints) {
  // 1 cm of noise across 2 cm spacing: a band of 0.3 s (6 mm) holds under
  // half of a face.
  const std::vector<Eigen::Vector3d> points = CornerPoints(0.02, 0.01);
  const LineValidator validator(LineValidationOptions(), points);
  EXPECT_NEAR(validator.noise(), 0.01, 0.003);
  EXPECT_NEAR(validator.plane_tolerance(), 2.5 * validator.noise(), 1e-12);
  // Over 20 seeds, the crease found with the wider band lies within 4 mm
  // of the true one; with the band of the spacing alone it strays farther.
  LineValidationOptions spacing_only;
  spacing_only.plane_tolerance_sigmas = 0;
  const LineValidator narrow(spacing_only, points);
  const Eigen::Vector3d start(-1, 0.01, 0.01);
  const Eigen::Vector3d end(1, 0.01, 0.01);
  double worst_wide = 0;
  double worst_narrow = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const ValidatedLine wide_line = validator.Validate(start, end, seed);
    ASSERT_EQ(wide_line.status, LineValidationStatus::kCrease)
        << LineValidationStatusName(wide_line.status);
    worst_wide = std::max(worst_wide,
                          std::hypot(wide_line.start.y(), wide_line.start.z()));
    const ValidatedLine narrow_line = narrow.Validate(start, end, seed);
    if (narrow_line.status == LineValidationStatus::kCrease) {
      worst_narrow = std::max(worst_narrow, std::hypot(narrow_line.start.y(),
                                                       narrow_line.start.z()));
    }
  }
  EXPECT_LT(worst_wide, 0.004);
  EXPECT_GT(worst_narrow, 0.005);
  // Noise-free points keep the band of the spacing.
  const LineValidator clean(LineValidationOptions(), CornerPoints(0.02, 0.0));
  EXPECT_LT(clean.noise(), 1e-6);
  EXPECT_NEAR(clean.plane_tolerance(), 0.3 * clean.spacing(), 1e-12);
}

TEST(LineValidation, OptionsAndInputAreChecked) {
  LineValidationOptions options;
  EXPECT_TRUE(options.Check());
  options.min_side_fraction = 0.5;
  EXPECT_FALSE(options.Check());
  options = LineValidationOptions();
  options.min_crease_angle_deg = 0;
  EXPECT_FALSE(options.Check());
  options = LineValidationOptions();
  options.max_offset_factor = -1;
  EXPECT_FALSE(options.Check());
  options = LineValidationOptions();
  options.max_faces = 1;
  EXPECT_FALSE(options.Check());
  options = LineValidationOptions();
  options.max_side_face_offset_factor = 2 * options.max_offset_factor;
  EXPECT_FALSE(options.Check());
  options = LineValidationOptions();
  options.plane_tolerance_sigmas = -1;
  EXPECT_FALSE(options.Check());
  options = LineValidationOptions();
  options.noise_radius_factor = 0;
  EXPECT_FALSE(options.Check());
  const std::vector<Eigen::Vector3d> few(3, Eigen::Vector3d::Zero());
  EXPECT_THROW(LineValidator(LineValidationOptions(), few), Error);
  // Coincident points: no crease, no hang (a 0.1 mm spacing floor, the
  // grid's box search bounded by its points).
  const std::vector<Eigen::Vector3d> same(100, Eigen::Vector3d::Ones());
  const LineValidator validator(LineValidationOptions(), same);
  EXPECT_NE(validator
                .Validate(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 1, 1), 1)
                .status,
            LineValidationStatus::kCrease);
}

}  // namespace
}  // namespace colmap_lidar
