// RenderErrorOf(f): the message of the RenderError that `f` throws, for the render tests.

#pragma once

#include <string>

#include "render/backend.h"

namespace corridorsim::test {

// The message of the RenderError `f` throws ("" when it throws nothing or something else).
template <typename F>
std::string RenderErrorOf(F&& f) {
  try {
    f();
  } catch (const render::RenderError& e) {
    return e.what();
  } catch (...) {
  }
  return "";
}

}  // namespace corridorsim::test
