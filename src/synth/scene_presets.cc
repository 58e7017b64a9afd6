#include "src/synth/scene_presets.h"

#include <sstream>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

const std::vector<std::string>& ScenePresetNames() {
  static const std::vector<std::string> kNames = {"quad", "street", "corridor",
                                                  "street_bent", "square"};
  return kNames;
}

std::string ScenePresetNamesText() {
  const std::vector<std::string>& names = ScenePresetNames();
  std::ostringstream text;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text << (i + 1 == names.size() ? " or " : ", ");
    text << names[i];
  }
  return text.str();
}

bool IsKnownScenePreset(const std::string& preset) {
  for (const std::string& name : ScenePresetNames()) {
    if (name == preset) return true;
  }
  return false;
}

SynthScene BuildScene(const std::string& preset, double length_factor) {
  if (!IsKnownScenePreset(preset)) {
    THROW_ERROR("Unknown Synthesis.preset '" << preset << "' (expected "
                                             << ScenePresetNamesText() << ")");
  }
  if (preset == "street_bent") return BuildStreetBentScene(length_factor);
  THROW_CHECK(length_factor == 1.0,
              "Synthesis.length_factor must be 1 for the preset '"
                  << preset << "' (only street_bent can be made longer)");
  if (preset == "quad") return BuildQuadScene();
  if (preset == "street") return BuildStreetScene();
  if (preset == "corridor") return BuildCorridorScene();
  return BuildSquareScene();
}

}  // namespace colmap_lidar
