#pragma once

#include <string>

#include "perception/mount_calibration.h"

namespace agv::pipeline {

// Reads TAGS.yaml for `agv calibrate mount`: `family: tag36h11` (optional) and
// `tags: [{id, size_m, x_m, y_m, yaw_rad}, ...]` (yaw_rad optional), poses in the vehicle frame.
// Throws InputError naming the file and the key (missing, mistyped, out of range, unknown,
// an id listed twice).
perception::FloorTagsFile load_floor_tags_file(const std::string& path);

}  // namespace agv::pipeline
