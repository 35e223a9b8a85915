// Python actions -> rdsim::Action, checked: type, shape, range, finiteness. Every problem is an
// rdsim::Error (rdsim.Error in Python) that says what was expected and what came.
#include <cmath>

#include "bindings.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim::python {
namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += std::to_string(a.shape(i)) + (a.ndim() == 1 || i + 1 < a.ndim() ? "," : "");
  return s + ")";
}

std::string got(const py::array& a) {
  return "got " + py::str(a.dtype()).cast<std::string>() + " of shape " + shape_text(a);
}

std::string discrete_expected(const ActionSpace& space) {
  return "an integer in [0, " + std::to_string(space.n - 1) + "] (Discrete(" + std::to_string(space.n) + "))";
}

std::string box_expected(const ActionSpace& space, const std::string& batch) {
  return "a float array of shape (" + batch + std::to_string(space.dim()) + ",) (Box)";
}

// The object as a NumPy array (lists and scalars too); rdsim::Error when NumPy cannot read it.
template <class What>
py::array as_array(const py::handle& h, What what) {
  if (py::isinstance<py::array>(h)) return py::reinterpret_borrow<py::array>(h);
  py::array a = py::array::ensure(h);
  if (!a) {
    PyErr_Clear();
    throw Error(what() + ", got a Python " + type_name(h));
  }
  if (a.dtype().kind() == 'O') throw Error(what() + ", got objects of type " + type_name(h));
  return a;
}

bool integer_kind(const py::array& a) { return a.dtype().kind() == 'i' || a.dtype().kind() == 'u'; }

// `what` builds the message's start ("actions: expected ...") only when there is an error.
template <class What>
void check_index(const ActionSpace& space, long long index, What what) {
  if (index < 0 || index >= space.n) throw Error(what() + ", got " + std::to_string(index));
}

template <class What>
void check_finite(const float* v, py::ssize_t n, What what) {
  for (py::ssize_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) throw Error(what() + " with finite values, got " + std::to_string(v[i]) + " at element " + std::to_string(i));
}

using Int64s = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;
using Floats = py::array_t<float, py::array::c_style | py::array::forcecast>;

}  // namespace

void read_action(const ActionSpace& space, const py::handle& action, Action& out) {
  if (space.discrete) {
    auto what = [&] { return "action: expected " + discrete_expected(space); };
    if (py::isinstance<py::bool_>(action)) throw Error(what() + ", got a bool");
    py::array a = as_array(action, what);
    if (a.ndim() != 0 || !integer_kind(a)) throw Error(what() + ", " + got(a));
    check_index(space, Int64s::ensure(a).at(), what);
    out.index = static_cast<int>(Int64s::ensure(a).at());
    return;
  }
  auto what = [&] { return "action: expected " + box_expected(space, ""); };
  py::array a = as_array(action, what);
  if (a.dtype().kind() != 'f' || a.ndim() != 1 || a.shape(0) != space.dim()) throw Error(what() + ", " + got(a));
  Floats f = Floats::ensure(a);
  check_finite(f.data(), f.size(), what);
  out.values = Eigen::Map<const Eigen::VectorXf>(f.data(), space.dim());
}

void read_actions(const ActionSpace& space, const py::handle& actions, std::vector<Action>& out) {
  const auto n = static_cast<py::ssize_t>(out.size());
  if (space.discrete) {
    auto what = [&] {
      return "actions: expected an integer array of shape (" + std::to_string(n) + ",), each " + discrete_expected(space);
    };
    py::array a = as_array(actions, what);
    if (a.ndim() != 1 || a.shape(0) != n || !integer_kind(a)) throw Error(what() + ", " + got(a));
    Int64s idx = Int64s::ensure(a);
    for (py::ssize_t i = 0; i < n; ++i) {
      check_index(space, idx.data()[i], what);
      out[static_cast<std::size_t>(i)].index = static_cast<int>(idx.data()[i]);
    }
    return;
  }
  auto what = [&] { return "actions: expected " + box_expected(space, std::to_string(n) + ", "); };
  py::array a = as_array(actions, what);
  if (a.dtype().kind() != 'f' || a.ndim() != 2 || a.shape(0) != n || a.shape(1) != space.dim()) throw Error(what() + ", " + got(a));
  Floats f = Floats::ensure(a);
  check_finite(f.data(), f.size(), what);
  const int dim = space.dim();
  for (py::ssize_t i = 0; i < n; ++i) {
    Eigen::VectorXf& v = out[static_cast<std::size_t>(i)].values;
    if (v.size() != dim) v.resize(dim);
    std::copy(f.data() + i * dim, f.data() + (i + 1) * dim, v.data());
  }
}

}  // namespace rdsim::python
