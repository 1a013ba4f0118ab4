// A problem at a line of an input file (a scene, a machine configuration): the message reads
// "file:line: what is wrong". Each kind of file has its own type, so a caller can tell a bad scene
// (exit 1) from a bad configuration (exit 2, like a bad command line).
#pragma once

#include <stdexcept>
#include <string>

namespace rtm {

class FileError : public std::runtime_error {
 public:
  FileError(const std::string& file, int line, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + what),
        file_(file),
        line_(line) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

}  // namespace rtm
