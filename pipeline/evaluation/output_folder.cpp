#include "pipeline/evaluation/output_folder.h"

#include <chrono>
#include <ctime>
#include <random>

#include "common/input_error.h"

namespace agv::pipeline {
namespace fs = std::filesystem;

namespace {

fs::path timestamped_run_folder() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm local{};
  localtime_r(&now, &local);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%d-%H%M%S", &local);
  fs::path candidate = fs::path("runs") / stamp;
  for (int n = 2; fs::exists(candidate); ++n)
    candidate = fs::path("runs") / (std::string(stamp) + "-" + std::to_string(n));
  return candidate;
}

}  // namespace

OutputFolder::OutputFolder(const std::string& target, const std::string& marker, bool replace) {
  target_ = target.empty() ? timestamped_run_folder() : fs::path(target);
  std::error_code error;
  if (fs::exists(target_, error)) {
    if (!fs::is_directory(target_, error))
      throw InputError(target_.string() + ": exists and is not a folder");
    if (!fs::is_empty(target_, error) && !replace) {
      throw InputError(target_.string() +
                       ": exists; pass --force to replace it, or choose another --out");
    }
    if (!fs::is_empty(target_, error) && !fs::exists(target_ / marker, error)) {
      throw InputError(target_.string() +
                       ": folder exists and does not hold a previous result (no " + marker +
                       "); choose another --out");
    }
  }
  const fs::path parent = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  fs::create_directories(parent, error);
  if (error)
    throw InputError(parent.string() + ": cannot create the output folder: " + error.message());
  std::random_device random;
  temporary_ =
      parent / ("." + target_.filename().string() + ".partial-" + std::to_string(random()));
  fs::create_directories(temporary_, error);
  if (error) throw InputError(temporary_.string() + ": cannot create a folder: " + error.message());
}

OutputFolder::~OutputFolder() {
  if (committed_) return;
  std::error_code error;
  fs::remove_all(temporary_, error);
}

void OutputFolder::commit() {
  std::error_code error;
  if (fs::exists(target_, error)) fs::remove_all(target_, error);
  fs::rename(temporary_, target_, error);
  if (error)
    throw InputError(target_.string() + ": cannot move the results into place: " + error.message());
  committed_ = true;
}

}  // namespace agv::pipeline
