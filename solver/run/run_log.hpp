#pragma once
// run.log in the output folder: what the terminal showed, for batch runs and for later. One line
// per event, each prefixed with the local date and time: the command, the model summary and the
// scene's warnings, the progress line every RunSettings::progress_interval s of wall time, and the
// outcome. Appended and flushed line by line (a killed run keeps what it logged); a fresh run
// moves the earlier run's run.log into previous/ with its other results, a resumed one appends.
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace adamss::solver {

class RunLog {
 public:
  explicit RunLog(std::filesystem::path file) : file_(std::move(file)) {}
  /// Logs one line; before open() lines are kept in memory (the folder must not change before
  /// the run has started) and written by open(). IoError naming the file when a write fails.
  void line(std::string_view text);
  /// Creates (or with `append`, extends) the file and writes the lines kept so far.
  void open(bool append);
  [[nodiscard]] const std::filesystem::path& file() const { return file_; }
  /// From now on lines are dropped and open() writes nothing (an MPI rank other than 0).
  void mute() {
    muted_ = true;
    pending_.clear();
  }

 private:
  void write(const std::string& stamped);
  std::filesystem::path file_;
  std::ofstream out_;
  bool open_ = false;
  bool muted_ = false;
  std::vector<std::string> pending_;
};

}  // namespace adamss::solver
