#pragma once
// VTK reports errors through events (or prints them); ErrorCatcher collects their text for one
// adamss error message instead. Shared by the .vtu writer and the .vtu importer.
#include <vtkCommand.h>

#include <algorithm>
#include <string>

namespace adamss::preprocess::vtk_io {

/// Observer of vtkCommand::ErrorEvent: `message` holds the errors seen, "; "-separated.
class ErrorCatcher : public vtkCommand {
 public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject* /*caller*/, unsigned long /*event*/, void* data) override {
    if (data != nullptr) {
      if (!message.empty()) message += "; ";
      std::string text = static_cast<const char*>(data);
      // VTK messages are multi-line ("ERROR: In file, line N\nclass (ptr): text\n"); keep the text.
      while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
      if (const auto colon = text.rfind("): "); colon != std::string::npos) text = text.substr(colon + 3);
      std::replace(text.begin(), text.end(), '\n', ' ');
      message += text;
    }
  }
  std::string message;
};

}  // namespace adamss::preprocess::vtk_io
