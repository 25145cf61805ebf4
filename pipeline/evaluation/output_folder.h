#pragma once

#include <filesystem>
#include <string>

namespace agv::pipeline {

// A run's output folder, written under a temporary name beside the target and renamed into
// place by commit(), so that an interrupted or failed run never leaves a folder that looks like
// a result. Without commit() the temporary folder is removed.
class OutputFolder {
 public:
  // `target` empty: runs/<YYYYmmdd-HHMMSS>[-N] under the working directory. An existing, non-empty
  // target is replaced only when `replace` (the user's --force) and only if it holds a previous
  // result (a file named `marker`, summary.json for runs); otherwise InputError.
  explicit OutputFolder(const std::string& target, const std::string& marker = "summary.json",
                        bool replace = false);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  // Path of a file inside the (temporary) folder.
  std::filesystem::path file(const std::string& name) const { return temporary_ / name; }
  const std::filesystem::path& target() const { return target_; }
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  bool committed_ = false;
};

}  // namespace agv::pipeline
