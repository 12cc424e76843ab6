// SPDX-License-Identifier: MIT
// libFuzzer target: the checkpoint reader (checkpoint.hpp). Any input is read or refused with
// tumble::InputError; a checkpoint that is read is written again, and that file must read back
// and write the same bytes (write ∘ read is the identity on what read accepts).
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>

#include "fuzz_util.hpp"
#include "tumble/checkpoint.hpp"
#include "tumble/error.hpp"

namespace {
std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tumble;
  const std::optional<Checkpoint> ck = fuzz::readCheckpoint(data, size);
  if (!ck) return 0;
  const std::string once = fuzz::scratchPath("once.ck"), twice = fuzz::scratchPath("twice.ck");
  ck->write(once);
  Checkpoint::read(once).write(twice);
  const std::string a = slurp(once), b = slurp(twice);
  if (a != b) fuzz::fail("a checkpoint read back and written again differs");
  if (a.size() > size) fuzz::fail("a checkpoint written again is longer than the one read");
  return 0;
}
