#include "src/synth/textures.h"

#include <algorithm>
#include <cmath>

#include "src/synth/random.h"

namespace colmap_lidar {
namespace {

double HashUnit(int64_t x, int64_t y, uint32_t seed) {
  const uint64_t h = HashCombine(
      HashCombine(static_cast<uint64_t>(seed), static_cast<uint64_t>(x)),
      static_cast<uint64_t>(y));
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

double SmoothStep(double t) { return t * t * (3.0 - 2.0 * t); }

// Distance (metres) from `value` to the nearest multiple of `period`.
double JointDistance(double value, double period) {
  const double r = value - period * std::floor(value / period);
  return std::min(r, period - r);
}

// 1 inside a block, falling to 0 in a joint of half width `half_width` with
// a soft 3 mm shoulder (joints are slightly recessed and shaded).
double JointMask(double distance, double half_width) {
  return std::clamp((distance - half_width) / 0.003 + 0.5, 0.0, 1.0);
}

Eigen::Vector3d Lerp(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                     double t) {
  return a + (b - a) * t;
}

// Running-bond brick: 215 x 65 mm bricks, 10 mm mortar.
Eigen::Vector3d Brick(const Eigen::Vector2d& uv, uint32_t seed) {
  const double course = 0.075;
  const double length = 0.225;
  const double row = std::floor(uv.y() / course);
  const double shift = (static_cast<int64_t>(row) & 1) ? 0.5 * length : 0.0;
  const double u = uv.x() + shift;
  const double column = std::floor(u / length);
  const double mortar = std::min(JointMask(JointDistance(uv.y(), course), 0.005),
                                 JointMask(JointDistance(u, length), 0.005));
  const double h1 = HashUnit(static_cast<int64_t>(column),
                             static_cast<int64_t>(row), seed);
  const double h2 = HashUnit(static_cast<int64_t>(column),
                             static_cast<int64_t>(row), seed ^ 0x5bd1e995u);
  // Per-brick hue and brightness; some darker (over-fired) bricks.
  Eigen::Vector3d brick(0.42 + 0.16 * h1, 0.17 + 0.08 * h1 + 0.04 * h2,
                        0.10 + 0.05 * h2);
  if (h2 > 0.85) brick *= 0.6;
  const double grain = FractalNoise(uv.x() * 60.0, uv.y() * 60.0, 2, seed + 7);
  brick *= 0.8 + 0.4 * grain;
  const double dirt = FractalNoise(uv.x() * 0.7, uv.y() * 0.7, 3, seed + 11);
  const Eigen::Vector3d mortar_colour =
      Eigen::Vector3d(0.55, 0.53, 0.48) *
      (0.9 + 0.2 * ValueNoise(uv.x() * 40, uv.y() * 40, seed + 3));
  return Lerp(mortar_colour, brick, mortar) * (0.75 + 0.5 * dirt);
}

// Ashlar limestone: 0.6 m courses of 0.45-1.0 m blocks, 8 mm joints.
Eigen::Vector3d Stone(const Eigen::Vector2d& uv, uint32_t seed) {
  const double course = 0.6;
  const double row = std::floor(uv.y() / course);
  const int64_t r = static_cast<int64_t>(row);
  // Block lengths vary per course: a fixed random length per course.
  const double length = 0.45 + 0.55 * HashUnit(r, 17, seed);
  const double shift = length * HashUnit(r, 23, seed);
  const double u = uv.x() + shift;
  const double column = std::floor(u / length);
  const double joint = std::min(JointMask(JointDistance(uv.y(), course), 0.004),
                                JointMask(JointDistance(u, length), 0.004));
  const double h = HashUnit(static_cast<int64_t>(column), r, seed);
  Eigen::Vector3d stone =
      Eigen::Vector3d(0.62, 0.57, 0.45) * (0.8 + 0.3 * h);
  const double grain = FractalNoise(uv.x() * 25.0, uv.y() * 25.0, 3, seed + 5);
  const double weathering =
      FractalNoise(uv.x() * 1.5, uv.y() * 1.5, 3, seed + 9);
  stone *= (0.75 + 0.5 * grain) * (0.7 + 0.5 * weathering);
  return Lerp(Eigen::Vector3d(0.30, 0.28, 0.25), stone, joint);
}

// Painted render: +-3% variation over metres, nothing finer.
Eigen::Vector3d Plaster(const Eigen::Vector2d& uv, uint32_t seed) {
  const double base = 0.97 + 0.06 * FractalNoise(uv.x() * 0.25,
                                                 uv.y() * 0.25, 2, seed);
  const double tint = HashUnit(seed, 3, 77);
  return Eigen::Vector3d(0.80, 0.76 - 0.06 * tint, 0.66 - 0.1 * tint) * base;
}

// Square 0.6 m slabs with 6 mm joints, per-slab shade, grit.
Eigen::Vector3d Paving(const Eigen::Vector2d& uv, uint32_t seed) {
  const double size = 0.6;
  const double joint = std::min(JointMask(JointDistance(uv.x(), size), 0.003),
                                JointMask(JointDistance(uv.y(), size), 0.003));
  const double h = HashUnit(static_cast<int64_t>(std::floor(uv.x() / size)),
                            static_cast<int64_t>(std::floor(uv.y() / size)),
                            seed);
  const double grit = FractalNoise(uv.x() * 40.0, uv.y() * 40.0, 2, seed + 1);
  const double stains = FractalNoise(uv.x() * 0.5, uv.y() * 0.5, 3, seed + 2);
  const Eigen::Vector3d slab = Eigen::Vector3d(0.45, 0.44, 0.42) *
                               (0.8 + 0.35 * h) * (0.75 + 0.5 * grit) *
                               (0.75 + 0.5 * stains);
  return Lerp(Eigen::Vector3d(0.2, 0.2, 0.19), slab, joint);
}

Eigen::Vector3d Glass(const Eigen::Vector2d& uv, uint32_t seed) {
  // Dark panes reflecting a little sky, with a soft gradient.
  const double g = 0.8 + 0.4 * ValueNoise(uv.x() * 0.8, uv.y() * 0.8, seed);
  return Eigen::Vector3d(0.05, 0.07, 0.09) * g;
}

Eigen::Vector3d Frame(const Eigen::Vector2d& uv, uint32_t seed) {
  const double g = 0.95 + 0.1 * FractalNoise(uv.x() * 5, uv.y() * 5, 2, seed);
  return Eigen::Vector3d(0.82, 0.82, 0.80) * g;
}

Eigen::Vector3d Wood(const Eigen::Vector2d& uv, uint32_t seed) {
  // Vertical planks 0.12 m wide with grain along v.
  const double plank = JointMask(JointDistance(uv.x(), 0.12), 0.002);
  const double grain = FractalNoise(uv.x() * 80.0, uv.y() * 4.0, 3, seed);
  const double h = HashUnit(static_cast<int64_t>(std::floor(uv.x() / 0.12)),
                            1, seed);
  const Eigen::Vector3d wood =
      Eigen::Vector3d(0.35, 0.20, 0.10) * (0.7 + 0.3 * h) * (0.7 + 0.6 * grain);
  return wood * (0.4 + 0.6 * plank);
}

Eigen::Vector3d Concrete(const Eigen::Vector2d& uv, uint32_t seed) {
  const double grit = FractalNoise(uv.x() * 30.0, uv.y() * 30.0, 3, seed);
  const double stains = FractalNoise(uv.x() * 1.0, uv.y() * 1.0, 2, seed + 4);
  return Eigen::Vector3d(0.5, 0.5, 0.48) * (0.7 + 0.4 * grit) *
         (0.8 + 0.3 * stains);
}

Eigen::Vector3d Foliage(const Eigen::Vector2d& uv, uint32_t seed) {
  const double n = FractalNoise(uv.x() * 12.0, uv.y() * 12.0, 3, seed);
  return Eigen::Vector3d(0.10 + 0.08 * n, 0.22 + 0.2 * n, 0.06 + 0.04 * n);
}

Eigen::Vector3d Bark(const Eigen::Vector2d& uv, uint32_t seed) {
  const double n = FractalNoise(uv.x() * 40.0, uv.y() * 6.0, 3, seed);
  return Eigen::Vector3d(0.25, 0.18, 0.12) * (0.6 + 0.8 * n);
}

Eigen::Vector3d Roof(const Eigen::Vector2d& uv, uint32_t seed) {
  return Eigen::Vector3d(0.3, 0.3, 0.32) *
         (0.8 + 0.4 * FractalNoise(uv.x(), uv.y(), 2, seed));
}

// Road asphalt: dark grey with fine aggregate (bright and dark stones of
// a few millimetres), slow patches of wear and tar; no joints.
Eigen::Vector3d Asphalt(const Eigen::Vector2d& uv, uint32_t seed) {
  const double aggregate =
      FractalNoise(uv.x() * 120.0, uv.y() * 120.0, 2, seed);
  const double grain = FractalNoise(uv.x() * 25.0, uv.y() * 25.0, 2, seed + 3);
  const double wear = FractalNoise(uv.x() * 0.3, uv.y() * 0.3, 3, seed + 6);
  const double g =
      0.11 * (0.65 + 0.7 * aggregate) * (0.85 + 0.3 * grain) * (0.8 + 0.4 * wear);
  return Eigen::Vector3d(g, g, 1.05 * g);
}

// Road marking paint: white with a little grit showing through where it is
// worn.
Eigen::Vector3d Paint(const Eigen::Vector2d& uv, uint32_t seed) {
  const double wear = FractalNoise(uv.x() * 4.0, uv.y() * 4.0, 3, seed);
  const double grit = ValueNoise(uv.x() * 90.0, uv.y() * 90.0, seed + 1);
  const double g = 0.78 * (0.9 + 0.1 * grit) * (wear > 0.8 ? 0.7 : 1.0);
  return Eigen::Vector3d(g, g, 0.97 * g);
}

}  // namespace

double ValueNoise(double x, double y, uint32_t seed) {
  const double fx = std::floor(x);
  const double fy = std::floor(y);
  const int64_t ix = static_cast<int64_t>(fx);
  const int64_t iy = static_cast<int64_t>(fy);
  const double tx = SmoothStep(x - fx);
  const double ty = SmoothStep(y - fy);
  const double v00 = HashUnit(ix, iy, seed);
  const double v10 = HashUnit(ix + 1, iy, seed);
  const double v01 = HashUnit(ix, iy + 1, seed);
  const double v11 = HashUnit(ix + 1, iy + 1, seed);
  return (v00 * (1 - tx) + v10 * tx) * (1 - ty) +
         (v01 * (1 - tx) + v11 * tx) * ty;
}

double FractalNoise(double x, double y, int octaves, uint32_t seed) {
  double sum = 0.0;
  double amplitude = 1.0;
  double total = 0.0;
  for (int octave = 0; octave < octaves; ++octave) {
    sum += amplitude * ValueNoise(x, y, seed + 1013u * octave);
    total += amplitude;
    amplitude *= 0.5;
    x = 2.03 * x + 17.1;
    y = 2.03 * y + 5.3;
  }
  return sum / total;
}

Eigen::Vector2d SurfaceCoordinates(const Eigen::Vector3d& point,
                                   const Eigen::Vector3d& normal) {
  if (std::abs(normal.z()) > 0.7) {
    return Eigen::Vector2d(point.x(), point.y());
  }
  const Eigen::Vector3d tangent =
      Eigen::Vector3d::UnitZ().cross(normal).normalized();
  return Eigen::Vector2d(point.dot(tangent), point.z());
}

Eigen::Vector3d MaterialAlbedo(Material material, const Eigen::Vector2d& uv,
                               uint32_t texture_seed) {
  switch (material) {
    case Material::kBrick: return Brick(uv, texture_seed);
    case Material::kStone: return Stone(uv, texture_seed);
    case Material::kPlaster: return Plaster(uv, texture_seed);
    case Material::kPaving: return Paving(uv, texture_seed);
    case Material::kGlass: return Glass(uv, texture_seed);
    case Material::kFrame: return Frame(uv, texture_seed);
    case Material::kWood: return Wood(uv, texture_seed);
    case Material::kConcrete: return Concrete(uv, texture_seed);
    case Material::kFoliage: return Foliage(uv, texture_seed);
    case Material::kBark: return Bark(uv, texture_seed);
    case Material::kRoof: return Roof(uv, texture_seed);
    case Material::kAsphalt: return Asphalt(uv, texture_seed);
    case Material::kPaint: return Paint(uv, texture_seed);
  }
  return Eigen::Vector3d(0.5, 0.5, 0.5);
}

}  // namespace colmap_lidar
