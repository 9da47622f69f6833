// A task whose body is a lambda, for trace tests.
#pragma once

#include <functional>
#include <vector>

#include "sched/scheduler.hpp"

namespace test {

class FnTask final : public fw::sched::Task {
 public:
  FnTask() = default;
  explicit FnTask(std::function<void(fw::sched::EventMask)> body) : body_(std::move(body)) {}
  void set(std::function<void(fw::sched::EventMask)> body) { body_ = std::move(body); }
  void run(fw::sched::EventMask events) override {
    received.push_back(events);
    if (body_) body_(events);
  }
  std::vector<fw::sched::EventMask> received;

 private:
  std::function<void(fw::sched::EventMask)> body_;
};

using Lines = std::vector<std::string>;

}  // namespace test
