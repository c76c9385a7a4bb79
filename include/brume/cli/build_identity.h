// Which build of brume is running, to key what it caches (brume bench's references): the
// FNV-1a hash of the executable's bytes, read from /proc/self/exe once per process, as 16 hex
// digits. Any rebuild that changes the executable changes it; an identical rebuild does not,
// rightly. Throws std::runtime_error (one line) if the executable cannot be read.
#pragma once
#include <string>

namespace brume::cli {

const std::string& buildIdentity();

}  // namespace brume::cli
