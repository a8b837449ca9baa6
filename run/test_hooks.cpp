#include "run/test_hooks.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <thread>

namespace radiosity::run {

void stallForTests(const char* stage) {
  const char* setting = std::getenv("RADIOSITY_TEST_STAGE_STALL");
  if (setting == nullptr) return;
  std::istringstream words(setting);
  std::string name;
  double seconds = 0;
  if (!(words >> name >> seconds) || name != stage || !(seconds > 0 && seconds < 1e4)) return;
  std::fprintf(stderr, "test hook: stalling %g s at the end of stage %s\n", seconds, stage);
  std::fflush(stderr);
  // sleep_until goes back to sleep after a signal's handler interrupted it.
  std::this_thread::sleep_until(std::chrono::steady_clock::now() +
                                std::chrono::duration<double>(seconds));
}

}  // namespace radiosity::run
