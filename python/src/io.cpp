// legkit.io: the log format of chapter 57.0 (io/log.hpp, io/log_columns.hpp) as NumPy columns.
//
// A Log stays the C++ io::Log (rows of fixed-size records), so that the estimators run on it with
// no conversion; its columns come out as new NumPy arrays (one copy per column: a column is
// strided across the row records). Log.from_columns goes through the kit's own strict reader, so
// that a log made in Python is checked exactly as a file would be.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <charconv>
#include <sstream>

#include "bindings.hpp"
#include "io/log_columns.hpp"
#include "io/log_error.hpp"
#include "io/log_reader.hpp"
#include "io/log_writer.hpp"

namespace py = pybind11;

namespace legkit::python {
namespace {

// The column `name` of every row, or a KeyError listing the log's columns.
py::array_t<double> column(const io::Log& log, const std::string& name) {
  const std::optional<io::Column> c = io::columnNamed(name);
  bool present = false;
  std::string known;
  for (const io::Column& k : io::columnsOf(log.layout)) {
    present = present || (c && k.field == c->field && k.foot == c->foot && k.index == c->index);
    known += (known.empty() ? "" : ", ") + k.name;
  }
  if (!present) throw py::key_error("no column '" + name + "' in this log; it has: " + known);
  py::array_t<double> out(static_cast<py::ssize_t>(log.rows.size()));
  auto v = out.mutable_unchecked<1>();
  for (std::size_t k = 0; k < log.rows.size(); ++k) {
    v(static_cast<py::ssize_t>(k)) = io::valueOf(log.rows[k], *c);
  }
  return out;
}

// Shortest text that parses back to exactly x (as io/log_writer.cpp writes numbers).
void appendNumber(std::string& s, double x) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), x);
  if (ec != std::errc()) throw std::logic_error("to_chars failed");
  s.append(buffer, end);
}

// A log from columns of equal length, read by the kit's reader from their CSV text: line L of a
// message is row L - 2 (line 1 is the header).
io::Log fromColumns(const py::dict& columns, const std::vector<std::string>& comments) {
  std::vector<std::string> names;
  std::vector<py::array_t<double, py::array::c_style | py::array::forcecast>> values;
  for (const auto& [key, value] : columns) {
    names.push_back(py::cast<std::string>(key));
    const py::array a = py::array::ensure(value);
    if (!a || a.ndim() != 1) {
      throw py::value_error("column '" + names.back() + "': expected a 1-D array of numbers");
    }
    if (a.dtype().kind() != 'f' && a.dtype().kind() != 'i' && a.dtype().kind() != 'u' &&
        a.dtype().kind() != 'b') {
      throw py::type_error("column '" + names.back() + "': expected numbers, got dtype " +
                           py::cast<std::string>(py::str(a.dtype())));
    }
    values.emplace_back(a);
    if (values.back().size() != values.front().size()) {
      throw py::value_error("column '" + names.back() + "' has " +
                            std::to_string(values.back().size()) + " rows, '" + names.front() +
                            "' has " + std::to_string(values.front().size()));
    }
  }
  if (names.empty()) throw py::value_error("from_columns: no columns");
  std::string text;
  for (std::size_t c = 0; c < names.size(); ++c) text += (c ? "," : "") + names[c];
  text += '\n';
  for (py::ssize_t r = 0; r < values.front().size(); ++r) {
    for (std::size_t c = 0; c < values.size(); ++c) {
      if (c) text += ',';
      appendNumber(text, values[c].at(r));
    }
    text += '\n';
  }
  std::istringstream in(text);
  io::Log log = io::readLog(in, "<from_columns>");
  log.comments = comments;
  return log;
}

const char* footCovarianceName(io::FootCovariance f) {
  return f == io::FootCovariance::kFull       ? "full"
         : f == io::FootCovariance::kDiagonal ? "diagonal"
                                              : "none";
}

}  // namespace

void bindIo(py::module_& m) {
  // LogError: a ValueError with the file, the 1-based line (0: none) and the column of the C++
  // io::LogError.
  static py::exception<io::LogError> log_error(m, "LogError", PyExc_ValueError);
  log_error.doc() =
      "A log that is not what the format says: str(e) is '<file>:<line>: column '<name>': what'; "
      "e.file, e.line (1-based, 0 when not tied to a line) and e.column (may be empty).";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const io::LogError& e) {
      py::object error = py::handle(log_error.ptr())(e.what());
      error.attr("file") = e.file();
      error.attr("line") = e.line();
      error.attr("column") = e.column();
      PyErr_SetObject(log_error.ptr(), error.ptr());
    }
  });

  py::class_<io::LogLayout>(m, "LogLayout",
                            "Which column groups a log carries (io/log.hpp LogLayout)")
      .def_readonly("joints", &io::LogLayout::joints, "q_<leg>_<j>, dq_<leg>_<j>: the quadruped")
      .def_readonly("torque", &io::LogLayout::torque, "tau_<leg>_<j> [N m]")
      .def_readonly("force", &io::LogLayout::force, "normal ground-reaction force per foot [N]")
      .def_readonly("contact", &io::LogLayout::contact, "contact flag per foot")
      .def_readonly("ground_truth", &io::LogLayout::ground_truth, "gt_p, gt_q (and gt_v)")
      .def_readonly("num_feet", &io::LogLayout::num_feet)
      .def_property_readonly(
          "foot_columns", [](const io::LogLayout& l) { return footCovarianceName(l.foot_columns); },
          "body-frame foot columns: 'none', 'diagonal' or 'full' covariance")
      .def_readonly("contact_truth", &io::LogLayout::contact_truth, "gt_contact_ ... (simulation)")
      .def_readonly("foot_velocity", &io::LogLayout::foot_velocity, "foot<k>_vx.. [m/s]")
      .def_readonly("gt_velocity", &io::LogLayout::gt_velocity, "gt_vx.. present")
      .def_readonly("gt_valid", &io::LogLayout::gt_valid, "a gt_valid column")
      .def_readonly("num_joints", &io::LogLayout::num_joints, "generic joint<k>_ columns")
      .def_readonly("joint_velocity", &io::LogLayout::joint_velocity,
                    "dq_ or joint<k>_dq present (else the front end differentiates the angles)")
      .def("__eq__", &io::LogLayout::operator==);

  py::class_<io::Log>(m, "Log",
                      "One run of a legged robot: one row per IMU sample (chapter 57.0). "
                      "log['gyro_x'] is a column as a new float64 array (a copy).")
      .def_readonly("layout", &io::Log::layout)
      .def_readonly("comments", &io::Log::comments, "the '#' lines before the header")
      .def_readonly("source", &io::Log::source, "the file it was read from, or '<from_columns>'")
      .def("__len__", [](const io::Log& log) { return log.rows.size(); })
      .def_property_readonly(
          "columns",
          [](const io::Log& log) {
            std::vector<std::string> names;
            for (const io::Column& c : io::columnsOf(log.layout)) names.push_back(c.name);
            return names;
          },
          "the column names, in the order the writer writes them")
      .def("__getitem__", &column, py::arg("name"),
           "The column `name` (a copy); KeyError if absent")
      .def("__contains__",
           [](const io::Log& log, const std::string& name) {
             for (const io::Column& c : io::columnsOf(log.layout)) {
               if (c.name == name) return true;
             }
             return false;
           })
      .def(
          "to_dict",
          [](const io::Log& log) {
            py::dict d;
            for (const io::Column& c : io::columnsOf(log.layout))
              d[c.name.c_str()] = column(log, c.name);
            return d;
          },
          "Every column by name (copies), in the writer's order")
      .def("line_of_row", &io::Log::lineOfRow, py::arg("k"),
           "The 1-based line of row k in its file")
      .def_static("from_columns", &fromColumns, py::arg("columns"),
                  py::arg("comments") = std::vector<std::string>{},
                  "A log from a dict of equal-length columns named as in a log file, checked by "
                  "the kit's strict reader (LogError: line L is row L - 2). Needs t, gyro_*, "
                  "acc_* and one leg description (chapter 57.0)");

  m.def(
      "read_log",
      [](const std::string& path, std::optional<double> max_gap) {
        return io::readLog(path, io::ReadOptions{max_gap});
      },
      py::arg("path"), py::arg("max_gap") = py::none(),
      "Reads a log CSV strictly (io/log_reader.hpp). max_gap [s]: the largest step allowed "
      "between timestamps (None: no bound). Raises LogError naming the file, line and column");
  m.def("write_log", py::overload_cast<const std::string&, const io::Log&>(&io::writeLog),
        py::arg("path"), py::arg("log"),
        "Writes a log CSV (every number in the shortest text that reads back exactly)");
}

}  // namespace legkit::python
