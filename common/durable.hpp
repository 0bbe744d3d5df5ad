#pragma once
// Durable replacement of a file: the data reach the disk before the file is renamed into place,
// and the rename itself is made durable, so that after a power loss or a kernel crash the target
// holds either the old or the new content, never an empty or partial file (a rename alone orders
// nothing: the renamed name can survive a crash while the data blocks did not).
#include <filesystem>
#include <initializer_list>
#include <string_view>

namespace adamss {

/// fsync of `file` (its data and metadata). IoError naming the file when it cannot be opened or
/// synced (e.g. EIO, a full disk reported late).
void sync_file(const std::filesystem::path& file);

/// fsync of the folder `dir`, making a rename or creation inside it durable. IoError as above.
void sync_directory(const std::filesystem::path& dir);

/// Writes every part to the open descriptor `fd`, the rest again after a short write or EINTR (a
/// part that fits the pipe or terminal goes out in one write(2)); the errno of the first failure
/// (EIO for a write of 0 bytes), else 0.
int write_all(int fd, std::initializer_list<std::string_view> parts);

/// Writes `parts` one after the other to `path`.tmp and renames it over `path`; with `durable`,
/// the data are fsync'ed before the rename and the folder after it. IoError naming the file and
/// the system's reason ("No space left on device") if anything fails; the .tmp is then removed
/// and `path` keeps its old content.
void replace_file(const std::filesystem::path& path, std::initializer_list<std::string_view> parts,
                  bool durable = false);

}  // namespace adamss
