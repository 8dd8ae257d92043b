// The error raised where input enters: names the file, the field (and line where known) and what
// is wrong. The command line turns it into exit code 2 (docs/commands.md).
#pragma once

#include <stdexcept>
#include <string>

namespace xsect {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::string field, std::string what, int line = -1)
      : std::runtime_error(format(file, field, what, line)),
        file_(std::move(file)), field_(std::move(field)), reason_(std::move(what)), line_(line) {}
  const std::string& file() const { return file_; }
  const std::string& field() const { return field_; }
  /// What is wrong, without the file, line and field.
  const std::string& reason() const { return reason_; }
  int line() const { return line_; }

 private:
  static std::string format(const std::string& file, const std::string& field,
                            const std::string& what, int line) {
    std::string s = file.empty() ? std::string("input") : file;
    if (line > 0) s += ":" + std::to_string(line);
    if (!field.empty()) s += ": " + field;
    return s + ": " + what;
  }
  std::string file_, field_, reason_;
  int line_;
};

}  // namespace xsect
