#pragma once
// The one way bolo writes an output folder: whole or not at all.

#include <filesystem>
#include <functional>

namespace bolo::rec {

// The contents are written into a hidden temporary sibling (`path()`, `.OUT.tmp-<pid>-<n>`) and
// commit() renames it to the destination in one rename(2). With `overwrite` an existing
// destination is first renamed aside (`.OUT.old-<pid>-<n>`), the new folder renamed into place,
// then the old one removed; if that rename fails the old one is put back. Destroyed without
// commit(), the temporary folder is removed. Every failure throws rec::Error naming the folder.
class AtomicFolder {
 public:
  // Called on an existing destination before it is replaced (at construction and at commit);
  // throws to refuse. The default refuses anything but a folder.
  using ReplaceCheck = std::function<void(const std::filesystem::path& existing)>;

  AtomicFolder(std::filesystem::path destination, bool overwrite, ReplaceCheck may_replace = {});
  ~AtomicFolder();
  AtomicFolder(const AtomicFolder&) = delete;
  AtomicFolder& operator=(const AtomicFolder&) = delete;

  const std::filesystem::path& path() const { return temporary_; }
  const std::filesystem::path& destination() const { return destination_; }
  bool committed() const { return committed_; }
  void commit();

 private:
  std::filesystem::path destination_, temporary_;
  bool overwrite_;
  ReplaceCheck may_replace_;
  bool committed_ = false;
};

}  // namespace bolo::rec
