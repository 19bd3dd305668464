#pragma once
/// @file
/// Test-only: measures heap allocations made through operator new while a probe is alive, so
/// tests can assert that decoding hostile bytes never allocates in proportion to a forged count.
/// allocation_probe.cc replaces the global operator new/delete of the test executable (malloc and
/// free underneath, so AddressSanitizer still sees every allocation). Single-threaded use.

#include <cstddef>

namespace mvtrack::transport::testing {

/// Records the largest single request and the total of all requests made while it is alive.
/// Probes do not nest.
class AllocationProbe {
 public:
  AllocationProbe();
  ~AllocationProbe();
  AllocationProbe(const AllocationProbe&) = delete;
  AllocationProbe& operator=(const AllocationProbe&) = delete;

  /// Largest single operator new request so far, bytes.
  std::size_t largest() const;
  /// Sum of all operator new requests so far, bytes.
  std::size_t total() const;
};

}  // namespace mvtrack::transport::testing
