// libFuzzer's entry points for one fuzz target (TASKMATRIX_FUZZ_TARGET), built with clang
// (-DTASKMATRIX_LIBFUZZER=ON; scripts/fuzz.sh). An exception other than core::InputError
// escapes and libFuzzer reports it with the input, as it reports crashes and timeouts.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  taskmatrix::fuzz::set_up(TASKMATRIX_FUZZ_ROOT);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const taskmatrix::fuzz::Target* target =
      taskmatrix::fuzz::find_target(TASKMATRIX_FUZZ_TARGET);
  taskmatrix::fuzz::run(*target, data, size);
  return 0;
}
