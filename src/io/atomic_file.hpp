// Crash-safe file writing: the content goes to NAME.tmp in the same directory, which is
// flushed, closed and checked before being renamed onto NAME. rename() within one directory
// is atomic on POSIX, so readers (and a later restart) only ever see the old complete file or
// the new complete file, never a half-written one.
#pragma once
#include <filesystem>
#include <functional>
#include <ostream>

namespace skred {

// Calls `write` with a binary output stream and atomically replaces `file` with what it
// wrote. Throws std::runtime_error naming `file` if the temporary file cannot be opened,
// written or renamed; an exception thrown by `write` itself is passed on unchanged. On any
// failure the temporary file is removed and an existing `file` is left untouched.
void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& write);

// The temporary path used for `file`: the same name with ".tmp" appended.
std::filesystem::path temporary_path_for(const std::filesystem::path& file);

}  // namespace skred
