#include "transport/allocation_probe.h"

#include <cstdlib>
#include <new>

namespace {

// Test-executable state of the probe (tests are single-threaded).
struct ProbeState {
  bool armed = false;
  std::size_t largest = 0;
  std::size_t total = 0;
};

ProbeState& State() {
  static ProbeState state;
  return state;
}

void* Allocate(std::size_t size) {
  ProbeState& state = State();
  if (state.armed) {
    if (size > state.largest) state.largest = size;
    state.total += size;
  }
  void* p = std::malloc(size == 0 ? 1 : size);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

}  // namespace

// Replacements of the global allocation functions (C++ [replacement.functions]).
void* operator new(std::size_t size) { return Allocate(size); }
void* operator new[](std::size_t size) { return Allocate(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return Allocate(size);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return Allocate(size);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace mvtrack::transport::testing {

AllocationProbe::AllocationProbe() {
  ProbeState& state = State();
  state = ProbeState{};
  state.armed = true;
}

AllocationProbe::~AllocationProbe() { State().armed = false; }

std::size_t AllocationProbe::largest() const { return State().largest; }
std::size_t AllocationProbe::total() const { return State().total; }

}  // namespace mvtrack::transport::testing
