#include "src/mvs/patch_match.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "colmap_ext/util/logging.h"
#include "src/mvs/parallel_rows.h"
#include "src/mvs/random.h"

namespace colmap_lidar {
namespace {

constexpr float kInitialDepthPerturbation = 0.1f;   // Relative.
constexpr float kInitialNormalPerturbation = 0.4f;  // Radians, roughly.
constexpr float kMinPerturbation = 0.004f;
// Propagation strips reach this many pixels (odd).
constexpr int kStripLength = 7;

Eigen::Vector3f RandomFacingNormal(const Eigen::Vector3f& ray,
                                   PixelRandom* random) {
  Eigen::Vector3f normal = random->UnitVector();
  if (normal.dot(ray) > 0) normal = -normal;
  return normal;
}

float RandomDepth(float depth_min, float depth_max, PixelRandom* random) {
  const float inv = random->Uniform(1.0f / depth_max, 1.0f / depth_min);
  return 1.0f / inv;
}

class PixelUpdater {
 public:
  PixelUpdater(const PatchMatchProblem& problem,
               const LidarPatchMatchOptions& options, PlaneMap* state)
      : problem_(problem),
        cost_(*problem.cost),
        ref_(cost_.Ref()),
        state_(state),
        prior_weight_(static_cast<float>(options.lidar_prior_weight)),
        prior_tolerance_(static_cast<float>(options.lidar_prior_tolerance)),
        strip_length_(options.far_propagation ? 2 * kStripLength + 1
                                              : kStripLength) {}

  float PriorTerm(size_t index, float depth) const {
    if (problem_.prior_depth == nullptr || prior_weight_ <= 0) return 0.0f;
    const float prior = (*problem_.prior_depth)[index];
    if (!(prior > 0)) return 0.0f;
    return prior_weight_ *
           std::min(std::abs(depth - prior) / (prior * prior_tolerance_), 1.0f);
  }

  float TotalCost(const RefPatch& patch, size_t index, float depth,
                  const Eigen::Vector3f& normal) const {
    return cost_.Cost(patch, depth, normal) + PriorTerm(index, depth);
  }

  void InitialCost(int row, int col, RefPatch* patch) {
    const size_t i = state_->Index(row, col);
    cost_.PrepareRefPatch(row, col, patch);
    state_->cost[i] = TotalCost(*patch, i, state_->depth[i], state_->normal[i]);
  }

  void Update(int row, int col, int iteration, uint64_t seed, RefPatch* patch) {
    const size_t i = state_->Index(row, col);
    cost_.PrepareRefPatch(row, col, patch);
    const Eigen::Vector3f ray = ref_.Ray(row, col);
    float best_depth = state_->depth[i];
    Eigen::Vector3f best_normal = state_->normal[i];
    float best_cost = state_->cost[i];
    auto consider = [&](float depth, const Eigen::Vector3f& normal) {
      if (!(depth >= problem_.depth_min && depth <= problem_.depth_max) ||
          normal.dot(ray) >= 0) {
        return;
      }
      const float cost = TotalCost(*patch, i, depth, normal);
      if (cost < best_cost) {
        best_cost = cost;
        best_depth = depth;
        best_normal = normal;
      }
    };
    // Propagation: per direction (up, down, left, right) the neighbour of
    // lowest cost among those 1, 3, ..., kStripLength pixels away (all of
    // the other colour), its plane intersected with this pixel's ray. Picking
    // by the stored cost costs no NCC evaluation and spreads good planes
    // kStripLength pixels per half-iteration instead of one (Xu and Tao
    // 2019's adaptive checkerboard sampling, with strips only).
    static constexpr int kDirections[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
    for (int k = 0; k < 4; ++k) {
      int best_j = -1;
      float best_neighbour_cost = std::numeric_limits<float>::infinity();
      for (int distance = 1; distance <= strip_length_; distance += 2) {
        const int r = row + distance * kDirections[k][0];
        const int c = col + distance * kDirections[k][1];
        if (r < 0 || c < 0 || r >= state_->height || c >= state_->width) break;
        const size_t j = state_->Index(r, c);
        if (!(state_->depth[j] > 0)) continue;
        if (best_j < 0 || state_->cost[j] < best_neighbour_cost) {
          best_j = static_cast<int>(j);
          best_neighbour_cost = state_->cost[j];
        }
      }
      if (best_j < 0) continue;
      const int r = best_j / state_->width;
      const int c = best_j % state_->width;
      const Eigen::Vector3f& normal = state_->normal[best_j];
      const float denominator = normal.dot(ray);
      if (denominator >= -1e-6f) continue;
      const float depth =
          normal.dot(state_->depth[best_j] * ref_.Ray(r, c)) / denominator;
      consider(depth, normal);
    }
    // Random refinement.
    PixelRandom random(seed, iteration, i);
    const float scale = std::pow(0.5f, static_cast<float>(iteration));
    const float depth_step =
        std::max(kInitialDepthPerturbation * scale, kMinPerturbation);
    const float normal_step =
        std::max(kInitialNormalPerturbation * scale, kMinPerturbation);
    const float current_depth = best_depth;
    const Eigen::Vector3f current_normal = best_normal;
    auto perturb_normal = [&]() {
      Eigen::Vector3f normal =
          (current_normal + normal_step * random.UnitVector()).normalized();
      if (normal.dot(ray) >= 0) normal = current_normal;
      return normal;
    };
    consider(current_depth * (1.0f + random.Uniform(-depth_step, depth_step)),
             perturb_normal());
    consider(current_depth, perturb_normal());
    consider(RandomDepth(problem_.depth_min, problem_.depth_max, &random),
             RandomFacingNormal(ray, &random));
    state_->depth[i] = best_depth;
    state_->normal[i] = best_normal;
    state_->cost[i] = best_cost;
  }

 private:
  const PatchMatchProblem& problem_;
  const PatchCostComputer& cost_;
  const MvsView& ref_;
  PlaneMap* state_;
  const float prior_weight_;
  const float prior_tolerance_;
  const int strip_length_;
};

}  // namespace

void RandomizePlaneMap(const MvsView& ref, float depth_min, float depth_max,
                       uint64_t seed, PlaneMap* state) {
  *state = PlaneMap(ref.width, ref.height);
  for (int row = 0; row < ref.height; ++row) {
    for (int col = 0; col < ref.width; ++col) {
      const size_t i = state->Index(row, col);
      PixelRandom random(seed, 1000003, i);
      state->depth[i] = RandomDepth(depth_min, depth_max, &random);
      state->normal[i] = RandomFacingNormal(ref.Ray(row, col), &random);
    }
  }
}

void RunPatchMatch(const PatchMatchProblem& problem,
                   const LidarPatchMatchOptions& options, int num_iterations,
                   uint64_t seed, PlaneMap* state,
                   const PatchMatchCallback& on_iteration) {
  THROW_CHECK(problem.cost != nullptr, "PatchMatchProblem without a cost");
  THROW_CHECK(problem.depth_min > 0 && problem.depth_max > problem.depth_min,
              "bad PatchMatch depth range [" << problem.depth_min << ", "
                                             << problem.depth_max << "]");
  const MvsView& ref = problem.cost->Ref();
  THROW_CHECK(state->width == ref.width && state->height == ref.height,
              "PatchMatch state " << state->width << "x" << state->height
                                  << " does not match view " << ref.name);
  // Replace unusable hypotheses by random planes.
  for (int row = 0; row < ref.height; ++row) {
    for (int col = 0; col < ref.width; ++col) {
      const size_t i = state->Index(row, col);
      const Eigen::Vector3f ray = ref.Ray(row, col);
      if (!(state->depth[i] >= problem.depth_min &&
            state->depth[i] <= problem.depth_max) ||
          !(state->normal[i].dot(ray) < 0)) {
        PixelRandom random(seed, 1000003, i);
        state->depth[i] =
            RandomDepth(problem.depth_min, problem.depth_max, &random);
        state->normal[i] = RandomFacingNormal(ray, &random);
      }
    }
  }
  PixelUpdater updater(problem, options, state);
  ParallelForRows(ref.height, options.num_threads, [&](int row) {
    RefPatch patch;
    for (int col = 0; col < ref.width; ++col) {
      updater.InitialCost(row, col, &patch);
    }
  });
  for (int iteration = 0; iteration < num_iterations; ++iteration) {
    for (int color = 0; color < 2; ++color) {
      ParallelForRows(ref.height, options.num_threads, [&](int row) {
        RefPatch patch;
        for (int col = (row + color) % 2; col < ref.width; col += 2) {
          updater.Update(row, col, iteration, seed, &patch);
        }
      });
    }
    if (on_iteration) on_iteration(iteration, *state);
  }
}

}  // namespace colmap_lidar
