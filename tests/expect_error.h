// The check the file-reading tests share: a call must refuse its input with an InputError (exit
// code 3) whose message names every given word.
#pragma once

#include <gtest/gtest.h>

#include <exception>
#include <string>
#include <vector>

#include "core/error.h"

namespace radiosity::testing {

/// Expects `call` to throw InputError (exit code 3) on this rank, mentioning every word.
template <class Call>
void expectInputError(Call call, const std::vector<std::string>& mentions) {
  try {
    call();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.exitCode(), exit_code::kBadInput);
    for (const std::string& word : mentions)
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos)
          << "'" << word << "' not in: " << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
  }
}

}  // namespace radiosity::testing
