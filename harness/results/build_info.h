// What this binary was built from, embedded at build time (cmake/build_info.cmake runs before
// every build): the git commit of the source tree, whether tracked files had changes, the
// SHA-256 of those changes (git diff HEAD; "" when clean), `git describe --always --dirty` and
// the CMake build type. "unknown" / "" when the sources were not a git checkout.
#pragma once

namespace taskmatrix::harness {

const char* build_commit();
bool build_dirty();
const char* build_diff_sha256();
const char* build_describe();
const char* build_type();

}  // namespace taskmatrix::harness
