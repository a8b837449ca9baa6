// Private to solve/: PETSc objects owned by C++ scopes, as io/ owns HDF5's. A PetscCall returns
// early from the function it fails in, so every object the function holds is freed by its
// handle's destructor, and every change made in place to an object it does not own is taken
// back by a ScopeGuard: nothing leaks and nothing is left half done, on any path out (an
// exception from a caller's callback included). Destructors cannot return an error code: a
// failure there is reported through PETSc's error handler (PetscCallVoid), never thrown.
#pragma once

#include <petscksp.h>

#include <memory>
#include <type_traits>
#include <utility>

namespace radiosity::solve {

/// Destroys a PETSc object with its Destroy function; a failure is reported, not thrown.
template <class Object, PetscErrorCode (*destroy)(Object*)>
struct Destroyer {
  using pointer = Object;
  void operator()(Object object) const noexcept { PetscCallVoid(destroy(&object)); }
};

/// Owns one PETSc object (or one reference to it) and destroys it at the end of its scope: a
/// std::unique_ptr that converts to the raw object for PETSc's calls. out() is the address to
/// create the object into.
template <class Object, PetscErrorCode (*destroy)(Object*)>
class Handle : public std::unique_ptr<std::remove_pointer_t<Object>, Destroyer<Object, destroy>> {
 public:
  Handle() = default;
  operator Object() const { return this->get(); }  // NOLINT: the object in PETSc calls

  /// What out() returns: converts to the Object* a PETSc Create or Duplicate writes to, and
  /// hands what was written to the handle at the end of the call's full-expression (like
  /// C++23's std::out_ptr), before the call's error code is checked.
  class Out {
   public:
    explicit Out(Handle& handle) : handle_(handle) {}
    ~Out() { handle_.reset(object_); }
    Out(const Out&) = delete;
    Out& operator=(const Out&) = delete;
    operator Object*() { return &object_; }  // NOLINT: passed as PETSc's output argument

   private:
    Handle& handle_;
    Object object_ = nullptr;
  };
  /// Frees what the handle holds (when the call's expression ends) and takes the new object.
  Out out() { return Out(*this); }
};

using OwnedMat = Handle<Mat, MatDestroy>;
using OwnedVec = Handle<Vec, VecDestroy>;
using OwnedKsp = Handle<KSP, KSPDestroy>;
using OwnedIs = Handle<IS, ISDestroy>;

/// A second reference to `object` (PetscObjectReference), owned by `handle`: for a handle that
/// works on an object someone else owns too, such as the shared matrix.
template <class Object, PetscErrorCode (*destroy)(Object*)>
PetscErrorCode shareInto(Object object, Handle<Object, destroy>& handle) {
  PetscFunctionBeginUser;
  PetscCall(PetscObjectReference(reinterpret_cast<PetscObject>(object)));
  handle.reset(object);
  PetscFunctionReturn(0);
}

/// Runs `undo` (a callable returning PetscErrorCode) when the scope ends, unless it already ran:
/// for a change made in place that every way out must take back. On the ordinary path, call
/// undoNow() to run it where it belongs and propagate its error; on an error path the
/// destructor runs it and reports its own failure through PETSc's error handler.
template <class Undo>
class ScopeGuard {
 public:
  explicit ScopeGuard(Undo undo) : undo_(std::move(undo)) {}
  ~ScopeGuard() {
    if (pending_) {
      pending_ = false;
      PetscCallVoid(undo_());
    }
  }
  ScopeGuard(const ScopeGuard&) = delete;
  ScopeGuard& operator=(const ScopeGuard&) = delete;

  PetscErrorCode undoNow() {
    pending_ = false;
    return undo_();
  }

 private:
  Undo undo_;
  bool pending_ = true;
};

}  // namespace radiosity::solve
