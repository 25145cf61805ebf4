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
const std::vector<std::string> kOptional = {"x_m",   "y_m",      "yaw_rad",  "e_theta_rad",
                                            "e_d_m", "odom_x_m", "odom_y_m", "odom_yaw_rad"};

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
  return extension == ".avi" || extension == ".mp4" || extension == ".mkv" || extension == ".mov" ||
         extension == ".webm";
}

namespace {

bool looks_like_image(const fs::path& path) {
  const std::string extension = lower(path.extension().string());
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg" ||
         extension == ".bmp" || extension == ".tif" || extension == ".tiff";
}

// The columns of manifest.csv by name, checked against the known ones.
std::map<std::string, int> read_header(const std::string& line, const std::string& manifest) {
  std::map<std::string, int> column;
  const std::vector<std::string> header = split_csv(line);
  for (int i = 0; i < static_cast<int>(header.size()); ++i) {
    const std::string& name = header[i];
    if (std::find(kRequired.begin(), kRequired.end(), name) == kRequired.end() &&
        std::find(kOptional.begin(), kOptional.end(), name) == kOptional.end()) {
      throw InputError(manifest + ": line 1: unknown column '" + name + "'");
    }
    if (column.count(name))
      throw InputError(manifest + ": line 1: column '" + name + "' appears twice");
    column[name] = i;
  }
  for (const std::string& name : kRequired) {
    if (!column.count(name)) throw InputError(manifest + ": line 1: missing column '" + name + "'");
  }
  return column;
}

// One row of manifest.csv, with the columns the header has.
DatasetRow read_row(const std::vector<std::string>& fields, std::map<std::string, int>& column,
                    const std::string& where) {
  auto number = [&](const char* name) { return parse_number(fields[column[name]], where, name); };
  auto has = [&](std::initializer_list<const char*> names) {
    for (const char* name : names)
      if (!column.count(name)) return false;
    return true;
  };
  DatasetRow row;
  const double index = number("index");
  if (index < 0 || index != std::floor(index))
    throw InputError(where + ": column 'index': expected a whole number >= 0");
  row.index = static_cast<int>(index);
  row.t_s = number("t_s");
  row.file = fields[column["file"]];
  if (row.file.empty()) throw InputError(where + ": column 'file': empty");
  if (has({"x_m", "y_m", "yaw_rad"}))
    row.pose = Pose2{number("x_m"), number("y_m"), number("yaw_rad")};
  if (has({"e_theta_rad", "e_d_m"}))
    row.truth = control::TrackingError{number("e_theta_rad"), number("e_d_m")};
  if (has({"odom_x_m", "odom_y_m", "odom_yaw_rad"}))
    row.odometry = Pose2{number("odom_x_m"), number("odom_y_m"), number("odom_yaw_rad")};
  return row;
}

void read_manifest(Dataset* d, bool allow_missing_frames) {
  std::ifstream in(d->manifest);
  std::string line;
  if (!std::getline(in, line))
    throw InputError(d->manifest + ": empty file, expected a header line");
  std::map<std::string, int> column = read_header(line, d->manifest);
  const size_t columns = split_csv(line).size();
  d->has_truth = column.count("e_theta_rad") && column.count("e_d_m");
  d->has_odometry =
      column.count("odom_x_m") && column.count("odom_y_m") && column.count("odom_yaw_rad");
  std::error_code error;
  for (int line_number = 2; std::getline(in, line); ++line_number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = d->manifest + ": line " + std::to_string(line_number);
    const std::vector<std::string> fields = split_csv(line);
    if (fields.size() != columns) {
      throw InputError(where + ": " + std::to_string(fields.size()) + " fields, the header has " +
                       std::to_string(columns));
    }
    DatasetRow row = read_row(fields, column, where);
    row.line = line_number;
    if (!d->rows.empty()) {
      if (row.index <= d->rows.back().index)
        throw InputError(where + ": index " + std::to_string(row.index) + " does not increase");
      if (row.t_s <= d->rows.back().t_s)
        throw InputError(where + ": t_s does not increase (frames must be in time order)");
    }
    if (!allow_missing_frames && !fs::is_regular_file(d->root / row.file, error)) {
      throw InputError(where + ": frame file '" + row.file + "' not found in " + d->root.string());
    }
    d->rows.push_back(row);
  }
  if (d->rows.empty()) throw InputError(d->manifest + ": no frames listed");
}

// A bare folder: its images (or those of its frames/), in name order, fps frames per second.
void list_bare_folder(Dataset* d, double fps) {
  std::error_code error;
  fs::path folder = d->root;
  if (fs::is_directory(folder / "frames", error)) folder /= "frames";
  const std::vector<fs::path> images = image_files_in(folder);
  if (images.empty()) {
    throw InputError(d->root.string() +
                     ": no manifest.csv and no images (PNG, JPEG, BMP, TIFF); expected a dataset "
                     "folder (frames/, manifest.csv, camera.yaml) or a folder of images");
  }
  if (!(fps > 0.0)) {
    throw InputError(d->root.string() + ": no manifest.csv, so the " +
                     std::to_string(images.size()) +
                     " images have no times: give their frame rate with --fps");
  }
  for (size_t i = 0; i < images.size(); ++i) {
    DatasetRow row;
    row.index = static_cast<int>(i);
    row.t_s = i / fps;
    row.file = fs::relative(images[i], d->root, error).string();
    d->rows.push_back(row);
  }
}

}  // namespace

std::vector<fs::path> image_files_in(const fs::path& folder) {
  std::error_code error;
  std::vector<fs::path> images;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    if (entry.is_regular_file(error) && looks_like_image(entry.path()))
      images.push_back(entry.path());
  }
  std::sort(images.begin(), images.end());
  return images;
}

Dataset open_dataset(const std::string& path, const std::string& camera_path, double fps,
                     bool allow_missing_frames) {
  Dataset d;
  std::error_code error;
  if (!fs::exists(path, error)) throw InputError(path + ": no such dataset folder");
  if (!fs::is_directory(path, error)) {
    throw InputError(path +
                     ": is a file; expected a dataset folder (frames/, manifest.csv, camera.yaml) "
                     "or a folder of images");
  }
  d.root = path;
  if (fs::exists(d.root / "manifest.csv", error)) {
    d.manifest = (d.root / "manifest.csv").string();
    read_manifest(&d, allow_missing_frames);
  } else {
    list_bare_folder(&d, fps);
  }
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
  manifest_ = "index,t_s,file,x_m,y_m,yaw_rad,e_theta_rad,e_d_m,odom_x_m,odom_y_m,odom_yaw_rad\n";
}

void DatasetWriter::add(int index, double t_s, const cv::Mat& frame, const Pose2& pose,
                        const control::TrackingError& truth, const Pose2& odometry) {
  char name[64];
  std::snprintf(name, sizeof(name), "frames/%06d.%s", index, format_ == "jpg" ? "jpg" : "png");
  const std::vector<int> parameters =
      format_ == "jpg" ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, jpeg_quality_}
                       : std::vector<int>{cv::IMWRITE_PNG_COMPRESSION, 6};
  if (!cv::imwrite((folder_ / name).string(), frame, parameters)) {
    throw InputError((folder_ / name).string() + ": cannot write the frame");
  }
  char row[384];
  std::snprintf(row, sizeof(row), "%d,%.6f,%s,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f\n", index,
                t_s, name, pose.x_m, pose.y_m, pose.yaw_rad, truth.e_theta_rad, truth.e_d_m,
                odometry.x_m, odometry.y_m, odometry.yaw_rad);
  manifest_ += row;
  ++frames_;
}

void DatasetWriter::finish() {
  std::ofstream out(folder_ / "manifest.csv");
  out << manifest_;
  if (!out) throw InputError((folder_ / "manifest.csv").string() + ": cannot write");
}

}  // namespace agv::pipeline
