#include "pipeline/config/floor_tags_file.h"

#include <fstream>
#include <sstream>

#include "common/input_error.h"
#include "pipeline/config/yaml_reader.h"

namespace agv::pipeline {

perception::FloorTagsFile load_floor_tags_file(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError(path + ": cannot be read");
  std::stringstream text;
  text << file.rdbuf();
  YamlReader in(parse_yaml(text.str(), path), path);
  perception::FloorTagsFile tags;
  tags.family = in.choice("family", tags.family, perception::AprilTagDetector::families());
  const size_t count = in.sequence_size("tags");
  if (count == 0) throw InputError(path + ": key 'tags': expected a non-empty list of tags");
  for (size_t i = 0; i < count; ++i) {
    const std::string key = "tags." + std::to_string(i);
    for (const char* field : {".id", ".size_m", ".x_m", ".y_m"}) {
      if (!in.has(key + field)) throw InputError(path + ": key '" + key + field + "': missing");
    }
    perception::FloorTagPose tag;
    tag.id = in.integer(key + ".id", 0, 0, 1000000);
    tag.size_m = in.number(key + ".size_m", 0.0, 0.001, 10.0);
    tag.x_m = in.number(key + ".x_m", 0.0, -100.0, 100.0);
    tag.y_m = in.number(key + ".y_m", 0.0, -100.0, 100.0);
    tag.yaw_rad = in.number(key + ".yaw_rad", 0.0, -10.0, 10.0);
    for (const perception::FloorTagPose& other : tags.tags) {
      if (other.id == tag.id)
        throw InputError(path + ": key '" + key + ".id': tag " + std::to_string(tag.id) +
                         " is listed twice");
    }
    tags.tags.push_back(tag);
  }
  in.finish();
  return tags;
}

}  // namespace agv::pipeline
