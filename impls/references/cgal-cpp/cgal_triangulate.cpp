// vorobench reference implementation: CGAL 2D Delaunay / regular triangulation as an
// executable following the vorobench protocol (docs: impl.toml next to this file).
//
// stdin : the sites, text (default) or binary (--binary).
//   text  : "n" or "n weighted" on the first line, then n rows "x y" or "x y w".
//   binary: u64 n (little endian), u8 flag (1 = weighted), n rows of 2 or 3 float64 (LE).
// stdout: one line "i j k" per finite face (0-based input indices), then "time SECONDS"
//         (the construction only: the range insert of the whole input).
//
// Modes (dispatched in main):
//   Mode::Delaunay  unweighted sites -> Delaunay_triangulation_2<Epick>
//   Mode::Regular   weighted sites   -> Regular_triangulation_2<Epick>, power |x-p|^2 - w
// A further mode (e.g. Apollonius_graph_2 for disks "x y r") is meant to be one more
// run_* function and one more enum value; the reading/writing code is shared.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Regular_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Regular_triangulation_vertex_base_2.h>
#include <CGAL/Regular_triangulation_face_base_2.h>
#include <CGAL/version.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;

// ---------------------------------------------------------------------------------------
// Errors: thrown as Input_error, reported by main on stderr with exit code 1.

struct Input_error : std::runtime_error {
  explicit Input_error(const std::string& what) : std::runtime_error(what) {}
};

// ---------------------------------------------------------------------------------------
// Input

struct Sites {
  std::size_t n = 0;
  int columns = 2;             // 2: x y; 3: x y w (or, for a future disk mode, x y r)
  std::vector<double> values;  // n * columns, row by row
  double at(std::size_t i, int c) const { return values[i * columns + c]; }
};

std::string read_all_stdin() {
  std::string data;
  std::size_t used = 0;
  data.resize(1 << 20);
  for (;;) {
    if (used == data.size()) data.resize(data.size() * 2);
    std::size_t got = std::fread(&data[used], 1, data.size() - used, stdin);
    used += got;
    if (got == 0) {
      if (std::ferror(stdin)) throw Input_error("error reading stdin");
      break;
    }
  }
  data.resize(used);
  return data;
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string describe_at(const char* p, const char* end) {
  std::size_t len = 0;
  while (p + len < end && len < 20 && p[len] != '\n') ++len;
  return "'" + std::string(p, len) + "'";
}

Sites parse_text(const std::string& data) {
  const char* p = data.data();
  const char* end = p + data.size();
  Sites s;

  // Header line: n [weighted]
  while (p < end && is_blank(*p)) ++p;
  {
    unsigned long long n = 0;
    auto r = std::from_chars(p, end, n);
    if (r.ec != std::errc() || r.ptr == p || (r.ptr < end && !is_space(*r.ptr)))
      throw Input_error("text input: header must start with the number of sites (an integer), got " + describe_at(p, end));
    s.n = static_cast<std::size_t>(n);
    p = r.ptr;
  }
  while (p < end && is_blank(*p)) ++p;
  const char* word = p;
  while (p < end && !is_space(*p)) ++p;
  std::string w(word, p);
  if (w.empty()) s.columns = 2;
  else if (w == "weighted") s.columns = 3;
  else throw Input_error("text input: unexpected word in header: '" + w + "' (only 'weighted' is allowed)");
  while (p < end && is_blank(*p)) ++p;
  if (p < end && *p != '\n')
    throw Input_error("text input: trailing characters in header: " + describe_at(p, end));

  // Rows: n lines of `columns` numbers each (blank lines/extra whitespace tolerated,
  // but each row must be on its own line).
  if (s.n > data.size()) throw Input_error("text input: n = " + std::to_string(s.n) + " but the input is too short");
  s.values.resize(s.n * s.columns);
  std::size_t k = 0;
  for (std::size_t i = 0; i < s.n; ++i) {
    // move to the start of the next line
    while (p < end && is_space(*p)) ++p;
    for (int c = 0; c < s.columns; ++c) {
      while (p < end && is_blank(*p)) ++p;
      if (p == end || *p == '\n')
        throw Input_error("text input: row " + std::to_string(i) + " has fewer than " +
                          std::to_string(s.columns) + " numbers (expected n = " + std::to_string(s.n) + " rows)");
      double v;
      auto r = std::from_chars(p, end, v);
      if (r.ec != std::errc() || r.ptr == p || (r.ptr < end && !is_space(*r.ptr)))
        throw Input_error("text input: row " + std::to_string(i) + ": not a number: " + describe_at(p, end));
      if (!std::isfinite(v))
        throw Input_error("text input: row " + std::to_string(i) + ": number is not finite: " + describe_at(p, end));
      s.values[k++] = v;
      p = r.ptr;
    }
    while (p < end && is_blank(*p)) ++p;
    if (p < end && *p != '\n')
      throw Input_error("text input: row " + std::to_string(i) + " has more than " +
                        std::to_string(s.columns) + " numbers: " + describe_at(p, end));
  }
  while (p < end && is_space(*p)) ++p;
  if (p != end)
    throw Input_error("text input: unexpected data after the " + std::to_string(s.n) + " rows: " + describe_at(p, end));
  return s;
}

Sites parse_binary(const std::string& data) {
  const unsigned char* b = reinterpret_cast<const unsigned char*>(data.data());
  if (data.size() < 9)
    throw Input_error("binary input: need at least 9 header bytes, got " + std::to_string(data.size()));
  std::uint64_t n = 0;
  for (int i = 7; i >= 0; --i) n = (n << 8) | b[i];
  unsigned flag = b[8];
  if (flag > 1) throw Input_error("binary input: flag byte must be 0 or 1, got " + std::to_string(flag));
  Sites s;
  s.columns = flag ? 3 : 2;
  std::uint64_t avail = (data.size() - 9) / (8u * s.columns);
  if ((data.size() - 9) % (8u * s.columns) != 0 || avail != n)
    throw Input_error("binary input: header says n = " + std::to_string(n) + (flag ? " weighted" : "") +
                      " (" + (n < (std::uint64_t(1) << 56) ? std::to_string(9 + n * 8 * s.columns) : std::string("too many")) +
                      " bytes expected) but got " + std::to_string(data.size()) + " bytes");
  s.n = static_cast<std::size_t>(n);
  s.values.resize(s.n * s.columns);
  const unsigned char* q = b + 9;
  for (std::size_t k = 0; k < s.values.size(); ++k, q += 8) {
    std::uint64_t bits = 0;
    for (int i = 7; i >= 0; --i) bits = (bits << 8) | q[i];
    double v;
    std::memcpy(&v, &bits, 8);
    if (!std::isfinite(v))
      throw Input_error("binary input: value " + std::to_string(k % s.columns) + " of row " +
                        std::to_string(k / s.columns) + " is not finite");
    s.values[k] = v;
  }
  return s;
}

// ---------------------------------------------------------------------------------------
// Output: everything goes into one string, written with fwrite at the end.

struct Output {
  std::string buf;
  double seconds = 0.0;

  void index(std::size_t v, char sep) {
    char tmp[24];
    auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
    buf.append(tmp, r.ptr);
    buf.push_back(sep);
  }
  void triangle(std::size_t i, std::size_t j, std::size_t k) {
    index(i, ' ');
    index(j, ' ');
    index(k, '\n');
  }
  void finish() {
    char tmp[64];
    int len = std::snprintf(tmp, sizeof tmp, "time %.9g\n", seconds);
    buf.append(tmp, static_cast<std::size_t>(len));
    std::size_t done = std::fwrite(buf.data(), 1, buf.size(), stdout);
    if (done != buf.size() || std::fflush(stdout) != 0) throw std::runtime_error("error writing stdout");
  }
};

typedef std::chrono::steady_clock Clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// Writes the finite faces of a 2D triangulation whose vertices carry their input index.
template <class Tr>
void write_faces(const Tr& tr, Output& out) {
  if (tr.dimension() < 2) return;  // collinear or n < 3: no triangles
  out.buf.reserve(out.buf.size() + tr.number_of_faces() * 24 + 64);
  for (auto f = tr.finite_faces_begin(); f != tr.finite_faces_end(); ++f)
    out.triangle(f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info());
}

// ---------------------------------------------------------------------------------------
// Mode::Delaunay

void run_delaunay(const Sites& s, Output& out) {
  typedef CGAL::Triangulation_vertex_base_with_info_2<std::size_t, K> Vb;
  typedef CGAL::Triangulation_data_structure_2<Vb> Tds;
  typedef CGAL::Delaunay_triangulation_2<K, Tds> DT;
  typedef K::Point_2 Point;

  std::vector<std::pair<Point, std::size_t>> pts;
  pts.reserve(s.n);
  for (std::size_t i = 0; i < s.n; ++i) pts.emplace_back(Point(s.at(i, 0), s.at(i, 1)), i);

  DT dt;
  auto t0 = Clock::now();
  dt.insert(pts.begin(), pts.end());  // spatial sort, then insertion
  auto t1 = Clock::now();
  out.seconds = seconds_between(t0, t1);
  write_faces(dt, out);
}

// ---------------------------------------------------------------------------------------
// Mode::Regular (power diagram's dual; weight = squared radius, power = |x-p|^2 - w)

void run_regular(const Sites& s, Output& out) {
  typedef CGAL::Regular_triangulation_vertex_base_2<K> Rvb;
  typedef CGAL::Triangulation_vertex_base_with_info_2<std::size_t, K, Rvb> Vb;
  typedef CGAL::Regular_triangulation_face_base_2<K> Fb;
  typedef CGAL::Triangulation_data_structure_2<Vb, Fb> Tds;
  typedef CGAL::Regular_triangulation_2<K, Tds> RT;
  typedef K::Point_2 Point;
  typedef K::Weighted_point_2 WPoint;

  std::vector<std::pair<WPoint, std::size_t>> pts;
  pts.reserve(s.n);
  for (std::size_t i = 0; i < s.n; ++i)
    pts.emplace_back(WPoint(Point(s.at(i, 0), s.at(i, 1)), s.at(i, 2)), i);

  RT rt;
  auto t0 = Clock::now();
  rt.insert(pts.begin(), pts.end());  // spatial sort, then insertion; hidden sites kept aside
  auto t1 = Clock::now();
  out.seconds = seconds_between(t0, t1);
  write_faces(rt, out);  // finite faces never contain hidden vertices
}

// ---------------------------------------------------------------------------------------

enum class Mode { Delaunay, Regular };

void usage(std::FILE* f) {
  std::fputs("usage: cgal_triangulate [--binary] [--version] < sites\n"
             "  text input (default): 'n [weighted]' then n rows 'x y' or 'x y w'\n"
             "  --binary: u64 n, u8 flag (1 = weighted), n rows of 2 or 3 float64, little endian\n",
             f);
}

}  // namespace

int main(int argc, char** argv) {
  bool binary = false;
  for (int a = 1; a < argc; ++a) {
    std::string arg = argv[a];
    if (arg == "--version") {
      std::printf("%s\n", CGAL_VERSION_STR);
      return 0;
    } else if (arg == "--binary") {
      binary = true;
    } else if (arg == "--help" || arg == "-h") {
      usage(stdout);
      return 0;
    } else {
      std::fprintf(stderr, "cgal_triangulate: unknown argument '%s'\n", argv[a]);
      usage(stderr);
      return 2;
    }
  }

  try {
    std::string data = read_all_stdin();
    Sites sites = binary ? parse_binary(data) : parse_text(data);
    std::string().swap(data);

    Mode mode = sites.columns == 3 ? Mode::Regular : Mode::Delaunay;
    Output out;
    switch (mode) {
      case Mode::Delaunay: run_delaunay(sites, out); break;
      case Mode::Regular: run_regular(sites, out); break;
    }
    out.finish();
  } catch (const Input_error& e) {
    std::fprintf(stderr, "cgal_triangulate: malformed input: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgal_triangulate: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
