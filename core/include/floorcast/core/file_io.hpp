// Whole-file reading and atomic writing, shared by every component's io part.
#pragma once

#include <string>

namespace floorcast {

/// Reads a whole file into a string; throws InputError naming the path on failure.
std::string read_text_file(const std::string& path);

/// Writes a whole file atomically (temporary file in the same folder, then rename).
void write_text_file_atomic(const std::string& path, const std::string& text);

/// Creates a directory and its parents; throws InputError naming it on failure.
void create_directories_or_throw(const std::string& path);

}  // namespace floorcast
