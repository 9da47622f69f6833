// Result<T>: a value or the Status that explains why there is none.
//
// Contract
// - A Result built from a value is ok(); one built from a Status must be given a failure (asserted).
// - value() on a failed Result is a programming error and goes to the fault handler; use valueOr() or test
//   ok() first. There is no way to read a value out of a failed Result by accident.
// - Trivially copyable when T is; no heap, no exceptions; usable from ISRs.
#pragma once

#include <type_traits>
#include <utility>

#include "core/assert.hpp"
#include "core/status.hpp"

namespace fw {

template <class T>
class Result {
  static_assert(std::is_default_constructible_v<T>, "Result<T> keeps a T in storage");

 public:
  constexpr Result(const T& value) : value_(value), status_(Status::Ok) {}  // NOLINT(implicit)
  constexpr Result(Status failure) : value_(), status_(failure) {           // NOLINT(implicit)
    FW_ASSERT_MODULE(::fw::Module::Core, failure != Status::Ok);
  }

  constexpr bool ok() const { return status_ == Status::Ok; }
  constexpr Status status() const { return status_; }

  constexpr const T& value() const {
    FW_ASSERT_MODULE(::fw::Module::Core, ok());
    return value_;
  }
  constexpr T valueOr(const T& fallback) const { return ok() ? value_ : fallback; }

 private:
  T value_;
  Status status_;
};

}  // namespace fw
