// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/gpu/pass_timer.h"

#include <fmt/format.h>

namespace translucent::gpu {

PassTimer::PassTimer() {
  GLint bits = 0;
  glGetQueryiv(GL_TIMESTAMP, GL_QUERY_COUNTER_BITS, &bits);
  if (bits <= 0)
    throw GlError("PassTimer: this OpenGL implementation has no GL_TIMESTAMP counter");
}

void PassTimer::begin(std::string name) {
  Pending p;
  p.name = std::move(name);
  p.depth = static_cast<int>(open_.size());
  p.start = Query::create(GL_TIMESTAMP);
  p.stop = Query::create(GL_TIMESTAMP);
  glQueryCounter(p.start.id(), GL_TIMESTAMP);
  checkGlError("glQueryCounter");
  open_.push_back(pending_.size());
  pending_.push_back(std::move(p));
}

void PassTimer::end() {
  if (open_.empty()) throw GlError("PassTimer::end() without an open pass");
  glQueryCounter(pending_[open_.back()].stop.id(), GL_TIMESTAMP);
  checkGlError("glQueryCounter");
  open_.pop_back();
}

void PassTimer::endNoThrow() noexcept {
  if (open_.empty()) return;  // nothing open (ended explicitly): nothing to end
  glQueryCounter(pending_[open_.back()].stop.id(), GL_TIMESTAMP);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR && deferred_error_.empty()) {
    try {
      deferred_error_ = fmt::format("PassTimer: glQueryCounter failed ending pass '{}' (GL error "
                                    "0x{:04x})", pending_[open_.back()].name, error);
    } catch (...) {
      deferred_error_ = "PassTimer: glQueryCounter failed ending a pass";
    }
  }
  while (glGetError() != GL_NO_ERROR) {
  }
  open_.pop_back();
}

PassTimer::Scope PassTimer::scope(std::string name) {
  begin(std::move(name));
  return Scope(*this);
}

std::vector<PassTimer::Pass> PassTimer::collect() {
  if (!deferred_error_.empty()) {
    const std::string message = std::move(deferred_error_);
    deferred_error_.clear();
    pending_.clear();
    open_.clear();
    throw GlError(message);
  }
  if (!open_.empty())
    throw GlError(fmt::format("PassTimer::collect() while pass '{}' is still open",
                              pending_[open_.back()].name));
  std::vector<Pass> out;
  out.reserve(pending_.size());
  for (const Pending& p : pending_) {
    GLuint64 t0 = 0, t1 = 0;
    glGetQueryObjectui64v(p.start.id(), GL_QUERY_RESULT, &t0);  // waits for the GPU
    glGetQueryObjectui64v(p.stop.id(), GL_QUERY_RESULT, &t1);
    // Timestamps are in nanoseconds.
    const double ns = t1 >= t0 ? static_cast<double>(t1 - t0) : 0.0;
    out.push_back({p.name, ns * 1e-6, p.depth});
  }
  checkGlError("glGetQueryObjectui64v");
  pending_.clear();
  last_ = out;
  return out;
}

double PassTimer::lastMs(std::string_view name) const {
  for (auto it = last_.rbegin(); it != last_.rend(); ++it)
    if (it->name == name) return it->ms;
  return -1.0;
}

}  // namespace translucent::gpu
