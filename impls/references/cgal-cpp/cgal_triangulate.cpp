// vorobench reference implementation: CGAL 2D Delaunay / regular triangulation / Apollonius
// graph as an executable following the vorobench protocol (docs: impl.toml next to this file).
//
// stdin : the sites, text (default) or binary (--binary).
//   text  : "n", "n weighted" or "n apollonius" on the first line, then n rows "x y",
//           "x y w" or "x y r".
//   binary: u64 n (little endian), u8 flag (0 = plain, 1 = weighted, 2 = apollonius),
//           n rows of 2 or 3 float64 (LE).
// stdout: Delaunay / regular: one line "i j k" per finite face (0-based input indices);
//         Apollonius: one line "i j k" per face of the graph, infinite ones included (-1 =
//         the infinite vertex), counter-clockwise as CGAL stores it;
//         then "time SECONDS" (the construction only: the insertion of the whole input).
//
// Modes (dispatched in main):
//   Mode::Delaunay    unweighted sites -> Delaunay_triangulation_2<Epick>
//   Mode::Regular     weighted sites   -> Regular_triangulation_2<Epick>, power |x-p|^2 - w
//   Mode::Apollonius  disks (r >= 0)   -> Apollonius_graph_2, distance |x-p| - r, exact
//                     filtered predicates (see run_apollonius)

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Regular_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Regular_triangulation_vertex_base_2.h>
#include <CGAL/Regular_triangulation_face_base_2.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Apollonius_graph_2.h>
#include <CGAL/Apollonius_graph_filtered_traits_2.h>
#include <CGAL/Apollonius_graph_vertex_base_2.h>
#include <CGAL/Triangulation_face_base_2.h>
#include <CGAL/version.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
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

enum class Kind { Plain, Weighted, Disks };

struct Sites {
  std::size_t n = 0;
  Kind kind = Kind::Plain;
  int columns = 2;             // 2: x y; 3: x y w (Weighted) or x y r (Disks)
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

  // Header line: n [weighted | apollonius]
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
  if (w.empty()) {
    s.kind = Kind::Plain;
    s.columns = 2;
  } else if (w == "weighted") {
    s.kind = Kind::Weighted;
    s.columns = 3;
  } else if (w == "apollonius") {
    s.kind = Kind::Disks;
    s.columns = 3;
  } else {
    throw Input_error("text input: unexpected word in header: '" + w + "' (only 'weighted' or 'apollonius' is allowed)");
  }
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
  if (flag > 2) throw Input_error("binary input: flag byte must be 0, 1 or 2, got " + std::to_string(flag));
  Sites s;
  s.kind = flag == 0 ? Kind::Plain : flag == 1 ? Kind::Weighted : Kind::Disks;
  s.columns = flag ? 3 : 2;
  std::uint64_t avail = (data.size() - 9) / (8u * s.columns);
  if ((data.size() - 9) % (8u * s.columns) != 0 || avail != n)
    throw Input_error("binary input: header says n = " + std::to_string(n) +
                      (flag == 1 ? " weighted" : flag == 2 ? " apollonius" : "") +
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

// Disks: the radius (third column) must be >= 0.
void check_radii(const Sites& s) {
  for (std::size_t i = 0; i < s.n; ++i)
    if (!(s.at(i, 2) >= 0.0))
      throw Input_error("apollonius input: row " + std::to_string(i) + ": radius is negative");
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
  // A vertex that may be the infinite one (Infinite: printed as -1).
  static constexpr std::size_t Infinite = std::numeric_limits<std::size_t>::max();
  void index_or_infinite(std::size_t v, char sep) {
    if (v == Infinite) {
      buf.append("-1", 2);
      buf.push_back(sep);
    } else {
      index(v, sep);
    }
  }
  // A face of the Apollonius graph: its three vertices counter-clockwise, then the line
  // numbers of its three neighbours, the one opposite each vertex in turn.
  void face(std::size_t i, std::size_t j, std::size_t k, std::size_t a, std::size_t b, std::size_t c) {
    index_or_infinite(i, ' ');
    index_or_infinite(j, ' ');
    index_or_infinite(k, ' ');
    index(a, ' ');
    index(b, ' ');
    index(c, '\n');
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
// Mode::Apollonius (the Apollonius graph: dual of the additively weighted Voronoi diagram of
// disks, distance from x to disk i = |x - c_i| - r_i)
//
// Traits: Apollonius_graph_filtered_traits_2<Simple_cartesian<double>,
// Integral_domain_without_division_tag>, i.e. with its defaults: the predicates are
// evaluated first in interval arithmetic (Simple_cartesian<Interval_nt<false>>) and, when
// that cannot decide, exactly in Simple_cartesian<MP_Float>; the Integral_domain_without_
// division_tag makes every predicate a sign of a ring expression (+, -, * only, the square
// roots eliminated by CGAL's algebra), so MP_Float decides it exactly. The constructions
// (unused here) would be in doubles. Sites are Apollonius_site_2 (point, weight = radius)
// built from the input doubles unchanged.
//
// Insertion: one site at a time in the input order, each walk for the nearest neighbour
// started at the vertex of the previous visible insertion (a hint only). Not the range
// insert: that one sorts the sites by decreasing weight (std::sort, unstable) first, which
// would make the choice among identical disks arbitrary. The walks cost about n^1.5 on
// random input (no spatial sort, no hierarchy): 10^5 random disks take seconds.
//
// Hidden sites (a disk inside another, touching included: CGAL's Is_hidden_2 is
// |c_p - c_q| <= r_q - r_p) get no vertex. Identical disks: CGAL tests "is the new site
// hidden by the existing nearest one" before "does the new site hide it", so of identical
// disks the one inserted first stays visible: with the input order, the smallest index
// (the convention of vorobench.core.hidden_disks too). The hidden sites are not stored
// (StoreHidden = false): nothing here needs them back (they matter only for removals).
//
// Indices: every vertex carries the input index of its site (Ag_vertex_with_index), set
// from the handle insert() returns (CGAL reuses a vertex for the new site in some cases, the
// returned handle is always the one holding it). CGAL recreates a surviving vertex in one
// case without returning it (a new disk hides all but one visible disk: the graph is
// cleared and rebuilt from two sites); after the construction every vertex's index is
// checked against its site, and any that does not match is looked up by its site among the
// input disks (the first index of identical ones), so the mapping does not depend on which
// vertices CGAL reuses or recreates.

template <class Gt, class Vb = CGAL::Apollonius_graph_vertex_base_2<Gt, false>>
class Ag_vertex_with_index : public Vb {
 public:
  typedef typename Vb::Site_2 Site_2;
  typedef typename Vb::Face_handle Face_handle;

  template <typename Tds2>
  struct Rebind_TDS {
    typedef typename Vb::template Rebind_TDS<Tds2>::Other Vb2;
    typedef Ag_vertex_with_index<Gt, Vb2> Other;
  };

  Ag_vertex_with_index() : Vb() {}
  Ag_vertex_with_index(const Site_2& p) : Vb(p) {}
  Ag_vertex_with_index(const Site_2& p, Face_handle f) : Vb(p, f) {}

  std::size_t index = Output::Infinite;  // input index of site(); Infinite = not set
};

void run_apollonius(const Sites& s, Output& out) {
  typedef CGAL::Simple_cartesian<double> CK;
  typedef CGAL::Apollonius_graph_filtered_traits_2<CK, CGAL::Integral_domain_without_division_tag> Gt;
  typedef Ag_vertex_with_index<Gt> Vb;
  typedef CGAL::Triangulation_face_base_2<Gt> Fb;
  typedef CGAL::Triangulation_data_structure_2<Vb, Fb> Agds;
  typedef CGAL::Apollonius_graph_2<Gt, Agds> AG;
  typedef AG::Site_2 Site;
  typedef AG::Point_2 Point;
  typedef AG::Vertex_handle Vertex_handle;
  typedef AG::Face_handle Face_handle;

  std::vector<Site> sites;
  sites.reserve(s.n);
  for (std::size_t i = 0; i < s.n; ++i) sites.emplace_back(Point(s.at(i, 0), s.at(i, 1)), s.at(i, 2));

  AG ag;
  auto t0 = Clock::now();
  Vertex_handle hint;
  for (std::size_t i = 0; i < s.n; ++i) {
    Vertex_handle v = ag.insert(sites[i], hint);  // null when the new site is hidden
    if (v != Vertex_handle()) {
      v->index = i;
      hint = v;  // alive: only an insertion that returns a vertex removes vertices
    }
  }
  auto t1 = Clock::now();
  out.seconds = seconds_between(t0, t1);

  // Check (and where needed repair) the index of every visible vertex; see above.
  auto same = [](const Site& a, const Site& b) {
    return a.x() == b.x() && a.y() == b.y() && a.weight() == b.weight();
  };
  for (auto v = ag.finite_vertices_begin(); v != ag.finite_vertices_end(); ++v) {
    if (v->index < s.n && same(sites[v->index], v->site())) continue;
    std::size_t found = Output::Infinite;
    for (std::size_t i = 0; i < s.n && found == Output::Infinite; ++i)
      if (same(sites[i], v->site())) found = i;
    if (found == Output::Infinite) throw std::runtime_error("a vertex of the Apollonius graph matches no input disk");
    v->index = found;
  }

  // No face lines below dimension 2 (fewer than three visible disks): the judge builds that
  // diagram itself. Otherwise every face, infinite ones included, with its neighbours: a
  // graph of disks may join two sites by several edges and a site to the infinite vertex by
  // several (a cell with several gaps at infinity), so the faces alone would not say which
  // face lies across which edge. Three disks on a path (no finite face) give infinite faces
  // only, each path edge with the infinite vertex on both sides; that is written out too.
  if (ag.dimension() < 2) return;
  std::unordered_map<const void*, std::size_t> line;
  line.reserve(ag.tds().number_of_faces());
  for (auto f = ag.all_faces_begin(); f != ag.all_faces_end(); ++f) {
    std::size_t next = line.size();
    line.emplace(&*f, next);
  }
  out.buf.reserve(out.buf.size() + ag.tds().number_of_faces() * 48 + 64);
  Vertex_handle inf = ag.infinite_vertex();
  auto idx = [&](Vertex_handle v) { return v == inf ? Output::Infinite : v->index; };
  auto across = [&](Face_handle f, int i) { return line.at(&*f->neighbor(i)); };
  for (auto f = ag.all_faces_begin(); f != ag.all_faces_end(); ++f)
    out.face(idx(f->vertex(0)), idx(f->vertex(1)), idx(f->vertex(2)), across(f, 0), across(f, 1), across(f, 2));
}

// ---------------------------------------------------------------------------------------

enum class Mode { Delaunay, Regular, Apollonius };

void usage(std::FILE* f) {
  std::fputs("usage: cgal_triangulate [--binary] [--version] < sites\n"
             "  text input (default): 'n [weighted | apollonius]' then n rows 'x y', 'x y w' or 'x y r'\n"
             "  --binary: u64 n, u8 flag (1 = weighted, 2 = apollonius), n rows of 2 or 3 float64,\n"
             "            little endian\n",
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

    if (sites.kind == Kind::Disks) check_radii(sites);

    Mode mode = sites.kind == Kind::Disks ? Mode::Apollonius
              : sites.kind == Kind::Weighted ? Mode::Regular : Mode::Delaunay;
    Output out;
    switch (mode) {
      case Mode::Delaunay: run_delaunay(sites, out); break;
      case Mode::Regular: run_regular(sites, out); break;
      case Mode::Apollonius: run_apollonius(sites, out); break;
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
