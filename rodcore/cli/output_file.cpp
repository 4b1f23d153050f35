#include "output_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "rodcore/checkpoint.hpp"
#include "rodcore/error.hpp"

namespace fs = std::filesystem;

namespace rodcore {
namespace {

std::vector<fs::path> made;  // folders made for the output, deepest last

std::string reason(int err) { return std::strerror(err); }

// The HDF5 signature, at byte 0 or, after a user block, at 512, 1024, 2048, ... (the HDF5 file
// format specification, "Superblock").
bool is_hdf5(const fs::path& p) {
  static const std::array<char, 8> signature{'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  std::ifstream in(p, std::ios::binary);
  if (!in) return false;
  std::error_code ec;
  const auto size = fs::file_size(p, ec);
  if (ec) return false;
  for (std::uintmax_t at = 0; at + signature.size() <= size; at = at ? 2 * at : 512) {
    std::array<char, 8> head{};
    in.seekg(static_cast<std::streamoff>(at));
    if (!in.read(head.data(), head.size())) return false;
    if (head == signature) return true;
  }
  return false;
}

// What a non-regular, non-folder thing is, for the message.
std::string kind_of(const fs::file_status& s) {
  switch (s.type()) {
    case fs::file_type::fifo:
      return "a FIFO (named pipe)";
    case fs::file_type::socket:
      return "a socket";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::character:
      return "a character device";
    default:
      return "not a regular file";
  }
}

// The files rodsim writes besides OUT: none of them may be a folder or a device.
void check_side_file(const std::string& what, const std::string& side) {
  std::error_code ec;
  const fs::file_status s = fs::status(side, ec);
  if (ec || !fs::exists(s) || fs::is_regular_file(s)) return;
  throw InputError(what + ": rodsim writes the file " + side + " while it runs, and that is " +
                   (fs::is_directory(s) ? std::string("a folder") : kind_of(s)) +
                   ": move it away or give another output name");
}

void make_parent_folders(const std::string& what, const fs::path& folder) {
  std::error_code ec;
  fs::path anchor = fs::absolute(folder, ec);  // then the deepest part that exists
  std::vector<fs::path> missing;
  while (!fs::exists(fs::symlink_status(anchor, ec)) && anchor != anchor.parent_path()) {
    missing.push_back(anchor);
    anchor = anchor.parent_path();
  }
  if (!fs::is_directory(anchor, ec))
    throw InputError(what + ": " + anchor.string() +
                     (fs::exists(anchor, ec) ? " is a file, not a folder" : " is a broken symbolic link") +
                     ", so nothing can be written under it");
  for (auto m = missing.rbegin(); m != missing.rend(); ++m) {
    if (::mkdir(m->c_str(), 0777) == 0) {
      made.push_back(*m);
      continue;
    }
    const int err = errno;
    if (err != EEXIST || !fs::is_directory(*m, ec))
      throw InputError(what + ": cannot create the folder " + m->string() + " (" + reason(err) + ")");
  }
}

// Write and remove a file in FOLDER: the one reliable test that the run's files can be made there.
void probe(const std::string& what, const fs::path& folder) {
  std::string name = (folder / ".rodsim-write-test-XXXXXX").string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0) throw InputError(what + ": cannot write in " + folder.string() + " (" + reason(errno) + ")");
  ::close(fd);
  ::unlink(name.c_str());
}

}  // namespace

void check_output_file(const std::string& out_path) {
  const std::string what = "-o " + out_path;
  if (out_path.empty()) throw InputError("-o: empty; give the output file's name, e.g. -o run.h5");
  const fs::path out(out_path);
  std::error_code ec;
  const fs::file_status s = fs::status(out, ec);
  if (fs::is_directory(s))
    throw InputError(what + ": is a folder; give a file name (rodsim writes one HDF5 file, e.g. " +
                     (out / "run.h5").string() + ")");
  if (!out.has_filename())
    throw InputError(what +
                     ": names a folder (it ends in '/'); give a file name (rodsim writes one HDF5 file)");
  if (fs::exists(s) && !fs::is_regular_file(s))
    throw InputError(what + ": is " + kind_of(s) + "; give a file name (rodsim writes one HDF5 file)");
  if (fs::is_regular_file(s) && fs::file_size(out, ec) > 0 && !is_hdf5(out))
    throw InputError(what + ": is an existing file that is not HDF5; rodsim replaces only an HDF5 file (the "
                            "output of an earlier run): give another name, or remove the file");
  check_side_file(what, out_path + ".partial");
  check_side_file(what, checkpoint_path(out_path));
  check_side_file(what, checkpoint_path(out_path) + ".tmp");
  const fs::path folder = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  make_parent_folders(what, folder);
  probe(what, folder);
}

void remove_made_folders() {
  while (!made.empty()) {
    std::error_code ec;
    fs::remove(made.back(), ec);  // only an empty folder: fs::remove never removes a folder's contents
    made.pop_back();
  }
}

}  // namespace rodcore
