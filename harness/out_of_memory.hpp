#pragma once
// What each of the harness's "ran out of host memory" sentences ends with: the two options
// that size a scene (a GPU's memory is checked before allocation, with its own sentence).
namespace sph {

inline constexpr const char* coarser_scene_advice = "choose a coarser spacing ('dp') or fewer 'particles'";

}  // namespace sph
