// MPI and PETSc for a whole test program: one solve::Runtime, started before the first test and
// ended after the last, with the PETSc options the program needs.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "solve/solve.h"

namespace radiosity::testing {

class PetscEnvironment : public ::testing::Environment {
 public:
  /// `arguments`: the program's name, then PETSc options (e.g. "-malloc_debug").
  explicit PetscEnvironment(std::vector<std::string> arguments)
      : arguments_(std::move(arguments)) {}
  void SetUp() override {
    for (std::string& argument : arguments_) argv_.push_back(argument.data());
    argv_.push_back(nullptr);
    runtime_ = std::make_unique<solve::Runtime>(static_cast<int>(arguments_.size()), argv_.data());
  }
  void TearDown() override { runtime_.reset(); }

 private:
  std::vector<std::string> arguments_;
  std::vector<char*> argv_;  ///< into arguments_, which PETSc may keep for the run
  std::unique_ptr<solve::Runtime> runtime_;
};

}  // namespace radiosity::testing
