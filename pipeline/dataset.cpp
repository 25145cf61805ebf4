#include "pipeline/dataset.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "common/input_error.h"

namespace agv::pipeline {
namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kRequired = {"index", "t_s", "file"};
const std::vector<std::string> kOptional = {"x_m", "y_m", "yaw_rad", "e_theta_rad", "e_d_m"};

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::stringstream stream(line);
  while (std::getline(stream, field, ',')) {
    while (!field.empty() && (field.back() == '\r' || field.back() == ' ')) field.pop_back();
    while (!field.empty() && field.front() == ' ') field.erase(field.begin());
    fields.push_back(field);
  }
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

double parse_number(const std::string& text, const std::string& where, const std::string& column) {
  size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (text.empty() || used != text.size())
    throw InputError(where + ": column '" + column + "': '" + text + "' is not a number");
  if (!std::isfinite(value))
    throw InputError(where + ": column '" + column + "': not a finite number");
  return value;
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), ::tolower);
  return text;
}

}  // namespace

bool looks_like_video(const std::string& path) {
  const std::string extension = lower(fs::path(path).extension().string());
  return extension == ".avi" || extension == ".mp4" || extension == ".mkv" || extension == ".mov";
}

Dataset open_dataset(const std::string& path, const std::string& camera_path, double video_fps,
                     bool allow_missing_frames) {
  Dataset d;
  std::error_code error;
  if (!fs::exists(path, error)) throw InputError(path + ": no such dataset folder or video file");
  if (!fs::is_directory(path, error)) {
    if (!looks_like_video(path)) {
      throw InputError(
          path +
          ": is a file; expected a dataset folder (frames/, manifest.csv, camera.yaml) or a "
          "video (.avi, .mp4, .mkv, .mov)");
    }
    if (camera_path.empty())
      throw InputError(path + ": a video carries no calibration; give one with --camera FILE");
    d.video = path;
    d.root = fs::path(path).parent_path();
    d.camera = perception::load_camera_file(camera_path);
    d.camera_name = camera_path;
    (void)video_fps;  // the rows of a video are made when it is read (its length is not trusted)
    return d;
  }
  d.root = path;
  d.manifest = (d.root / "manifest.csv").string();
  std::ifstream in(d.manifest);
  if (!in)
    throw InputError(
        path + ": no manifest.csv (expected index,t_s,file[,x_m,y_m,yaw_rad,e_theta_rad,e_d_m])");
  std::string line;
  if (!std::getline(in, line))
    throw InputError(d.manifest + ": empty file, expected a header line");
  const std::vector<std::string> header = split_csv(line);
  std::map<std::string, int> column;
  for (int i = 0; i < static_cast<int>(header.size()); ++i) {
    const std::string& name = header[i];
    if (std::find(kRequired.begin(), kRequired.end(), name) == kRequired.end() &&
        std::find(kOptional.begin(), kOptional.end(), name) == kOptional.end()) {
      throw InputError(d.manifest + ": line 1: unknown column '" + name + "'");
    }
    if (column.count(name))
      throw InputError(d.manifest + ": line 1: column '" + name + "' appears twice");
    column[name] = i;
  }
  for (const std::string& name : kRequired) {
    if (!column.count(name))
      throw InputError(d.manifest + ": line 1: missing column '" + name + "'");
  }
  const bool has_pose = column.count("x_m") && column.count("y_m") && column.count("yaw_rad");
  d.has_truth = column.count("e_theta_rad") && column.count("e_d_m");

  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = d.manifest + ": line " + std::to_string(line_number);
    const std::vector<std::string> fields = split_csv(line);
    if (fields.size() != header.size()) {
      throw InputError(where + ": " + std::to_string(fields.size()) + " fields, the header has " +
                       std::to_string(header.size()));
    }
    DatasetRow row;
    row.line = line_number;
    const double index = parse_number(fields[column["index"]], where, "index");
    if (index < 0 || index != std::floor(index))
      throw InputError(where + ": column 'index': expected a whole number >= 0");
    row.index = static_cast<int>(index);
    row.t_s = parse_number(fields[column["t_s"]], where, "t_s");
    row.file = fields[column["file"]];
    if (row.file.empty()) throw InputError(where + ": column 'file': empty");
    if (has_pose) {
      row.pose = Pose2{parse_number(fields[column["x_m"]], where, "x_m"),
                       parse_number(fields[column["y_m"]], where, "y_m"),
                       parse_number(fields[column["yaw_rad"]], where, "yaw_rad")};
    }
    if (d.has_truth) {
      row.truth =
          control::TrackingError{parse_number(fields[column["e_theta_rad"]], where, "e_theta_rad"),
                                 parse_number(fields[column["e_d_m"]], where, "e_d_m")};
    }
    if (!d.rows.empty()) {
      if (row.index <= d.rows.back().index)
        throw InputError(where + ": index " + std::to_string(row.index) + " does not increase");
      if (row.t_s <= d.rows.back().t_s)
        throw InputError(where + ": t_s does not increase (frames must be in time order)");
    }
    if (!allow_missing_frames && !fs::is_regular_file(d.root / row.file, error)) {
      throw InputError(where + ": frame file '" + row.file + "' not found in " + d.root.string());
    }
    d.rows.push_back(row);
  }
  if (d.rows.empty()) throw InputError(d.manifest + ": no frames listed");

  const std::string camera = camera_path.empty() ? (d.root / "camera.yaml").string() : camera_path;
  if (!fs::exists(camera, error)) {
    throw InputError(camera +
                     ": no camera file (a dataset holds camera.yaml; or give --camera FILE)");
  }
  d.camera = perception::load_camera_file(camera);
  d.camera_name = camera;
  return d;
}

DatasetWriter::DatasetWriter(const fs::path& folder, const perception::CameraFile& camera,
                             const std::string& format, int jpeg_quality)
    : folder_(folder), format_(format), jpeg_quality_(jpeg_quality) {
  std::error_code error;
  fs::create_directories(folder_ / "frames", error);
  if (error)
    throw InputError((folder_ / "frames").string() + ": cannot create: " + error.message());
  perception::save_camera_file((folder_ / "camera.yaml").string(), camera);
  manifest_ = "index,t_s,file,x_m,y_m,yaw_rad,e_theta_rad,e_d_m\n";
}

void DatasetWriter::add(int index, double t_s, const cv::Mat& frame, const Pose2& pose,
                        const control::TrackingError& truth) {
  char name[64];
  std::snprintf(name, sizeof(name), "frames/%06d.%s", index, format_ == "jpg" ? "jpg" : "png");
  const std::vector<int> parameters =
      format_ == "jpg" ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, jpeg_quality_}
                       : std::vector<int>{cv::IMWRITE_PNG_COMPRESSION, 6};
  if (!cv::imwrite((folder_ / name).string(), frame, parameters)) {
    throw InputError((folder_ / name).string() + ": cannot write the frame");
  }
  char row[256];
  std::snprintf(row, sizeof(row), "%d,%.6f,%s,%.9f,%.9f,%.9f,%.9f,%.9f\n", index, t_s, name,
                pose.x_m, pose.y_m, pose.yaw_rad, truth.e_theta_rad, truth.e_d_m);
  manifest_ += row;
  ++frames_;
}

void DatasetWriter::finish() {
  std::ofstream out(folder_ / "manifest.csv");
  out << manifest_;
  if (!out) throw InputError((folder_ / "manifest.csv").string() + ": cannot write");
}

}  // namespace agv::pipeline
