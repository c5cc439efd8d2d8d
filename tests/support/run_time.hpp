// at_run_time(v): v, read through a volatile, so that the compiler cannot fold what a test does
// with it. A constexpr function called with constants may be evaluated while compiling even at
// -O0 (a constant-initialised local), where gcov counts nothing: the coverage build's branch
// figure counts only what runs.
#ifndef MOTIONBUS_TESTS_RUN_TIME_HPP
#define MOTIONBUS_TESTS_RUN_TIME_HPP

namespace testutil {

template <class T>
T at_run_time(T v) {
  volatile T copy = v;
  return copy;
}

}  // namespace testutil

#endif  // MOTIONBUS_TESTS_RUN_TIME_HPP
