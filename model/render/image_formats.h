// Which files the image writers write, by name: one rule for the writers themselves and for
// rtm's check of its command line before a render starts.
#pragma once

#include <cctype>
#include <filesystem>
#include <string>

namespace rtm {

/// The file name's extension in lower case, with its dot (".png").
inline std::string image_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

/// write_image's formats: .png (8-bit) and .exr (float).
inline bool is_image_path(const std::string& path) {
  const std::string e = image_extension(path);
  return e == ".png" || e == ".exr";
}

/// An ID map's and a channel file's format: .exr.
inline bool is_exr_path(const std::string& path) { return image_extension(path) == ".exr"; }

}  // namespace rtm
