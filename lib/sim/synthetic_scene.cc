#include "sim/synthetic_scene.h"

#include <string>
#include <utility>

#include "core/check.h"

namespace mvtrack::sim {

Scene GenerateScene(const SceneOptions& options) {
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
  Scene scene;
  scene.options = options;
  scene.cameras = MakeCameras(options);
  const auto frames = static_cast<std::size_t>(options.num_frames);
  scene.truth.reserve(frames);
  scene.detections.reserve(frames);
  scene.detection_person_ids.reserve(frames);
  CrowdSimulator crowd(options);
  for (std::size_t f = 0; f < frames; ++f) {
    scene.truth.push_back(crowd.Next());
    RenderedFrame rendered = RenderFrame(options, scene.cameras, scene.truth.back());
    scene.detections.push_back(std::move(rendered.cameras));
    scene.detection_person_ids.push_back(std::move(rendered.person_ids));
  }
  return scene;
}

}  // namespace mvtrack::sim
