// AtomicFolder: a temporary sibling renamed into place.

#include "bolo/recording/atomic_folder.hpp"

#include <system_error>
#include <utility>

#include "bolo/recording/recording.hpp"
#include "detail.hpp"

namespace bolo::rec {
namespace fs = std::filesystem;
using detail::fail;

namespace {

bool exists_no_follow(const fs::path& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}

void refuse_non_folder(const fs::path& existing) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(existing, ec)))
    fail(existing, "exists and is not a folder; refusing to replace it");
}

}  // namespace

AtomicFolder::AtomicFolder(fs::path destination, bool overwrite, ReplaceCheck may_replace)
    : destination_(std::move(destination)),
      overwrite_(overwrite),
      may_replace_(may_replace ? std::move(may_replace) : ReplaceCheck(refuse_non_folder)) {
  if (destination_.empty() || destination_.filename() == "." || destination_.filename() == "..")
    throw Error("output folder '" + destination_.string() + "': not a valid destination name");
  if (exists_no_follow(destination_)) {
    if (!overwrite_) fail(destination_, "already exists (use --overwrite to replace it)");
    may_replace_(destination_);
  }
  const fs::path parent = destination_.parent_path().empty() ? fs::path(".") : destination_.parent_path();
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    fail(destination_, "the parent folder " + parent.string() + " does not exist");
  temporary_ = detail::temp_sibling(destination_, "tmp");
  if (!fs::create_directory(temporary_, ec) || ec)
    fail(temporary_, "cannot create the temporary folder: " + (ec ? ec.message() : "it already exists"));
}

AtomicFolder::~AtomicFolder() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(temporary_, ec);
}

void AtomicFolder::commit() {
  if (committed_) fail(destination_, "committed twice");
  std::error_code ec;
  if (exists_no_follow(destination_)) {
    if (!overwrite_) fail(destination_, "appeared while writing (use --overwrite to replace it)");
    may_replace_(destination_);
    const fs::path aside = detail::temp_sibling(destination_, "old");
    fs::rename(destination_, aside, ec);
    if (ec) fail(destination_, "cannot move the existing folder aside: " + ec.message());
    fs::rename(temporary_, destination_, ec);
    if (ec) {
      std::error_code ignored;
      fs::rename(aside, destination_, ignored);
      fail(destination_, "cannot rename the new folder into place: " + ec.message());
    }
    committed_ = true;
    fs::remove_all(aside, ec);
    if (ec) fail(aside, "the new folder is in place but the old one could not be removed: " + ec.message());
    return;
  }
  fs::rename(temporary_, destination_, ec);
  if (ec) fail(destination_, "cannot rename the new folder into place: " + ec.message());
  committed_ = true;
}

}  // namespace bolo::rec
