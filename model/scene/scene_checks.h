// The checks validate() runs, one per part of a scene, for the parsers to run as they read each
// part (so a message can name the file and line). Each throws std::invalid_argument.
#pragma once

#include <string>

#include "scene/scene.h"

namespace rtm::scene_checks {

void check_camera(const Camera& c);
void check_resolution(int width, int height);
void check_colour(const Vec3& c, const std::string& what);
void check_light(const Light& l);
void check_material(const Material& m);
void check_max_depth(int max_depth);
void check_grid(const GridOptions& g);

}  // namespace rtm::scene_checks
