/* delaunay.c: a Delaunay triangulation that follows the vorobench executable protocol.
 *
 * Reads "n" and then n lines "x y" on stdin, prints one line "i j k" per triangle
 * (0-based input indices) and a line "time SECONDS" for the construction alone.
 *
 * Algorithm: Bowyer-Watson incremental insertion, O(n^2). Start from a super-triangle that
 * contains every site; insert the sites one by one: the triangles whose circumcircle contains
 * the new site form a cavity (a star-shaped polygon around it), which is removed and
 * re-triangulated by joining its boundary edges to the site. At the end, the triangles
 * touching a super-triangle corner are dropped.
 *
 * The super-triangle's corners are "at infinity": a circle through one or two of them is
 * replaced by its limit, a half-plane, so no finite corner can ever be too close and cut
 * off a thin triangle on the convex hull.
 *
 * This is an example of the protocol, not a robust library: the predicates use plain
 * doubles, so it is meant for random input. On degenerate input (grids, cocircular or
 * nearly collinear sites) rounding may give a wrong triangulation. All-collinear input is
 * detected (exactly for small integer coordinates) and gives no triangles, as do n < 3.
 *
 * Build: cc -O2 -o delaunay delaunay.c -lm
 */
#define _POSIX_C_SOURCE 199309L              /* clock_gettime under strict C99 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

typedef struct { double x, y; } Point;
typedef struct { int v[3]; } Triangle;       /* counter-clockwise */

static int n;                                /* sites are 0..n-1; n, n+1, n+2 are the corners */
static Point *site;
/* Directions of the three corners at infinity, counter-clockwise: up, lower left, lower right. */
static const Point corner[3] = {{0, 1}, {-0.8660254037844386, -0.5}, {0.8660254037844386, -0.5}};

/* > 0 when a, b, c turn counter-clockwise: twice the signed area of the triangle. */
static double orient(Point a, Point b, Point c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/* > 0 when d lies inside the circle through a, b, c (counter-clockwise): the sign of the
 * 3x3 determinant of the points lifted onto the paraboloid z = x^2 + y^2, relative to d. */
static double incircle(Point a, Point b, Point c, Point d) {
    double ax = a.x - d.x, ay = a.y - d.y, bx = b.x - d.x, by = b.y - d.y;
    double cx = c.x - d.x, cy = c.y - d.y;
    return (ax * ax + ay * ay) * (bx * cy - cx * by) + (bx * bx + by * by) * (cx * ay - ax * cy)
         + (cx * cx + cy * cy) * (ax * by - bx * ay);
}

/* Whether site p lies inside the circumcircle of triangle t, corners at infinity included. */
static int in_circumcircle(const Triangle *t, int p) {
    int ghosts = (t->v[0] >= n) + (t->v[1] >= n) + (t->v[2] >= n);
    int r = 0;                                /* rotate t (keeping its orientation) so that */
    if (ghosts == 1) while (t->v[(r + 2) % 3] < n) r++;   /* a, b are sites, c a corner */
    if (ghosts == 2) while (t->v[r] >= n) r++;            /* a is a site, b, c corners */
    int a = t->v[r], b = t->v[(r + 1) % 3], c = t->v[(r + 2) % 3];
    Point P = site[p];
    if (ghosts == 0) return incircle(site[a], site[b], site[c], P) > 0;
    if (ghosts == 1) {
        /* The circle through a, b and a far point on the left of a->b tends to the half-plane
         * left of a->b; on the line itself it still contains the open segment ab. */
        double o = orient(site[a], site[b], P);
        if (o != 0) return o > 0;
        return (P.x - site[a].x) * (P.x - site[b].x) + (P.y - site[a].y) * (P.y - site[b].y) < 0;
    }
    if (ghosts == 2) {
        /* The circle through a and the far corners a + M d_b, a + M d_c has its centre at
         * a + M (d_b + d_c) = a - M d_k (unit directions 120 degrees apart, k the third
         * corner), so near a its inside tends to the half-plane (P - a) . d_k < 0. */
        int k = (n + n + 1 + n + 2) - b - c;  /* the corner that is neither b nor c */
        return (P.x - site[a].x) * corner[k - n].x + (P.y - site[a].y) * corner[k - n].y < 0;
    }
    return 1;                                 /* the super-triangle contains every site */
}

static int has_edge(const Triangle *t, int a, int b) {  /* directed edge a->b of t */
    for (int i = 0; i < 3; i++)
        if (t->v[i] == a && t->v[(i + 1) % 3] == b) return 1;
    return 0;
}

static int fail(const char *message) {
    fprintf(stderr, "%s\n", message);
    return 1;                                 /* the protocol's failure: a nonzero exit */
}

int main(void) {
    /* Input: n alone on the first line (weights are not supported), then n lines "x y". */
    if (scanf("%d", &n) != 1 || n < 0) return fail("expected n on the first line");
    int c = getchar();
    while (c == ' ' || c == '\t' || c == '\r') c = getchar();
    if (c != '\n' && c != EOF) return fail("weighted input is not supported");
    site = malloc((n + 1) * sizeof *site);
    for (int i = 0; i < n; i++)
        if (scanf("%lf %lf", &site[i].x, &site[i].y) != 2) return fail("expected n lines \"x y\"");

    struct timespec start, stop;
    clock_gettime(CLOCK_MONOTONIC, &start);

    int collinear = 1;                        /* sites are distinct, so 0 and 1 span a line */
    for (int i = 2; i < n && collinear; i++) collinear = orient(site[0], site[1], site[i]) == 0;

    int cap = 2 * n + 8, count = 0;           /* a triangulation of n + 3 points has <= 2n + 1 */
    Triangle *tri = malloc(cap * sizeof *tri), *cavity = malloc(cap * sizeof *cavity);
    int (*edge)[2] = malloc(3 * cap * sizeof *edge);
    if (!collinear) tri[count++] = (Triangle){{n, n + 1, n + 2}};
    for (int p = 0; p < n && !collinear; p++) {
        /* 1. Move the triangles whose circumcircle contains p out into the cavity. */
        int bad = 0;
        for (int t = 0; t < count; )
            if (in_circumcircle(&tri[t], p)) { cavity[bad++] = tri[t]; tri[t] = tri[--count]; }
            else t++;
        /* 2. The cavity's boundary: its edges that no other cavity triangle shares. */
        int edges = 0;
        for (int t = 0; t < bad; t++)
            for (int i = 0; i < 3; i++) {
                int a = cavity[t].v[i], b = cavity[t].v[(i + 1) % 3], shared = 0;
                for (int u = 0; u < bad && !shared; u++) shared = has_edge(&cavity[u], b, a);
                if (!shared) { edge[edges][0] = a; edge[edges][1] = b; edges++; }
            }
        if (bad == 0 || count + edges > cap) {   /* only when rounding broke the invariants */
            fprintf(stderr, "inconsistent predicates at site %d (degenerate input?)\n", p);
            return 1;
        }
        /* 3. Join each boundary edge a->b to p: p sees it from the left, so a, b, p turn
         *    counter-clockwise. */
        for (int e = 0; e < edges; e++) tri[count++] = (Triangle){{edge[e][0], edge[e][1], p}};
    }

    clock_gettime(CLOCK_MONOTONIC, &stop);
    for (int t = 0; t < count; t++)           /* drop the triangles touching a corner */
        if (tri[t].v[0] < n && tri[t].v[1] < n && tri[t].v[2] < n)
            printf("%d %d %d\n", tri[t].v[0], tri[t].v[1], tri[t].v[2]);
    printf("time %.17g\n", (stop.tv_sec - start.tv_sec) + 1e-9 * (stop.tv_nsec - start.tv_nsec));
    free(site); free(tri); free(cavity); free(edge);
    return 0;
}
