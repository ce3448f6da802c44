// A channel of half-width 1 with a smooth rigid stenosis centred at x = 0, upper half only (symmetry
// line y = 0), inflow at x = -upstream_length, outflow at x = downstream_length. The wall is
//   y = 1 - severity (1 - (2 x / length)^2)^3   for |x| < length / 2,   y = 1 elsewhere,
// so the half-width falls to 1 - severity at x = 0 (0.5 by default) over a length `length`, with the
// slope and the curvature continuous everywhere (the wall is C2; the cusp-free ends matter for the
// stress near the wall). That polynomial of degree 6 in x is exactly a Bezier curve: with t = x /
// length + 1/2, 1 - (2 x / length)^2 = 4 t (1 - t), so severity (1 - (2x / length)^2)^3 =
// 3.2 severity B_3^6(t) (B_3^6 = 20 t^3 (1 - t)^3), and the seven control points are equally spaced
// in x at height 1, but the middle one at 1 - 3.2 severity. Gmsh evaluates the wall exactly.
//
// Three structured blocks: upstream, throat (|x| < length / 2, the Bezier wall on top) and
// downstream. The throat has n_throat elements along it (uniform in arc length along the wall); the
// channel blocks are graded geometrically from an element of the throat's spacing at the stenosis.
// Across the channel, ny elements, graded towards the wall by wall_ratio (largest / smallest).
// -setnumber f 1, 2, 4 gives nested meshes, f multiplying every count and taking the f-th root of
// every progression factor.

SetFactory("Built-in");

// Every tunable number: -setnumber NAME VALUE (gmsh program, or the arguments of gmsh::initialize)
// or gmsh::onelab::setNumber("NAME", {VALUE}) before opening the file overrides it.
DefineConstant[
  f = {1, Name "f"},                                   // refinement (f 1, 2, 4 nest)
  severity = {0.5, Name "severity"},                   // the half-width at x = 0 is 1 - severity
  length = {4, Name "length"},                         // length of the stenosis
  upstream_length = {10, Name "upstream_length"},      // from the inflow to the stenosis' centre
  downstream_length = {20, Name "downstream_length"},  // from the stenosis' centre to the outflow
  n_throat = {8, Name "n_throat"},                     // elements along the stenosis for f = 1
  nx_upstream = {10, Name "nx_upstream"},              // elements upstream of the stenosis for f = 1
  nx_downstream = {16, Name "nx_downstream"},          // elements downstream of the stenosis for f = 1
  ny = {6, Name "ny"},                                 // elements across the channel for f = 1
  wall_ratio = {1, Name "wall_ratio"},                 // largest / smallest element across the channel, fine at the wall
  full = {0, Name "full"}                              // 1: the whole channel, -1 < y < 1, stenosed on both walls
];

Lu = upstream_length;
Ld = downstream_length;
a = 0.5 * length;

If (f < 1 || f != Round(f) || n_throat < 1 || n_throat != Round(n_throat) || nx_upstream < 1 ||
    nx_upstream != Round(nx_upstream) || nx_downstream < 1 || nx_downstream != Round(nx_downstream) ||
    ny < 1 || ny != Round(ny))
  Error("stenosis.geo: f, n_throat, nx_upstream, nx_downstream and ny must be whole numbers >= 1");
  Abort;
EndIf
If (severity <= 0 || severity >= 1)
  Error("stenosis.geo: severity must lie strictly between 0 and 1 (got %g): the half-width at the throat is 1 - severity", severity);
  Abort;
EndIf
If (length <= 0 || a >= Lu || a >= Ld)
  Error("stenosis.geo: length must be positive and length / 2 below upstream_length and downstream_length");
  Abort;
EndIf
If (full != 0 && full != 1)
  Error("stenosis.geo: full must be 0 (the upper half, a symmetry line at y = 0) or 1 (the whole channel); got %g", full);
  Abort;
EndIf
If (wall_ratio < 1)
  Error("stenosis.geo: wall_ratio is largest / smallest element and must be >= 1 (got %g)", wall_ratio);
  Abort;
EndIf

h = length / n_throat;  // the throat's spacing on f = 1, and the first channel element's size
If (h * nx_upstream >= Lu - a || h * nx_downstream >= Ld - a)
  Error("stenosis.geo: length / n_throat = %g times nx_upstream (nx_downstream) must stay below the channel's length upstream (downstream) of the stenosis", h);
  Abort;
EndIf

// The geometric factor pq > 1 of pn elements over a length pL whose first element is ph:
// ph (pq^pn - 1) / (pq - 1) = pL, by bisection. (A Call must stand on a line of its own.)
Macro Progression
  p_lo = 1;
  p_hi = 2;
  For p_k In {1:60}
    If ((p_hi^pn - 1) / (p_hi - 1) < pL / ph)
      p_hi = 2 * p_hi;
    EndIf
  EndFor
  For p_k In {1:200}
    p_mid = 0.5 * (p_lo + p_hi);
    If ((p_mid^pn - 1) / (p_mid - 1) < pL / ph)
      p_lo = p_mid;
    Else
      p_hi = p_mid;
    EndIf
  EndFor
  pq = 0.5 * (p_lo + p_hi);
Return

pn = nx_upstream;
pL = Lu - a;
ph = h;
Call Progression;
q_upstream = pq^(1 / f);
pn = nx_downstream;
pL = Ld - a;
Call Progression;
q_downstream = pq^(1 / f);
q_wall = wall_ratio^(1 / Max(ny - 1, 1));
q_wall = q_wall^(1 / f);

Point(1) = {-Lu, 0, 0};
Point(2) = {-a, 0, 0};
Point(3) = {a, 0, 0};
Point(4) = {Ld, 0, 0};
Point(5) = {-Lu, 1, 0};
Point(6) = {-a, 1, 0};
Point(7) = {a, 1, 0};
Point(8) = {Ld, 1, 0};
// the inner control points of the wall's Bezier curve
For k In {1:5}
  Point(8 + k) = {-a + k * length / 6, (k == 3) ? 1 - 3.2 * severity : 1, 0};
EndFor

Line(1) = {1, 2};  // symmetry
Line(2) = {2, 3};  // symmetry
Line(3) = {3, 4};  // symmetry
Line(4) = {1, 5};  // inflow
Line(5) = {4, 8};  // outflow
Line(6) = {5, 6};  // wall upstream
Bezier(7) = {6, 9, 10, 11, 12, 13, 7};  // wall along the stenosis
Line(8) = {7, 8};  // wall downstream
Line(9) = {2, 6};  // x = -length / 2 (interior)
Line(10) = {3, 7}; // x = length / 2 (interior)

Transfinite Curve{1, 6} = f * nx_upstream + 1 Using Progression 1 / q_upstream;
Transfinite Curve{2, 7} = f * n_throat + 1;
Transfinite Curve{3, 8} = f * nx_downstream + 1 Using Progression q_downstream;
Transfinite Curve{4, 9, 10, 5} = f * ny + 1 Using Progression 1 / q_wall;

Curve Loop(1) = {1, 9, -6, -4};
Plane Surface(1) = {1};  // upstream
Curve Loop(2) = {2, 10, -7, -9};
Plane Surface(2) = {2};  // throat
Curve Loop(3) = {3, 5, -8, -10};
Plane Surface(3) = {3};  // downstream

Transfinite Surface{1} = {1, 2, 6, 5};
Transfinite Surface{2} = {2, 3, 7, 6};
Transfinite Surface{3} = {3, 4, 8, 7};
Recombine Surface{1:3};

// full = 1: the mirror image below y = 0 (its wall stenosed the same way), and y = 0 interior
If (full == 1)
  Point(14) = {-Lu, -1, 0};
  Point(15) = {-a, -1, 0};
  Point(16) = {a, -1, 0};
  Point(17) = {Ld, -1, 0};
  For k In {1:5}
    Point(17 + k) = {-a + k * length / 6, (k == 3) ? -1 + 3.2 * severity : -1, 0};
  EndFor
  Line(11) = {14, 15};                          // lower wall upstream
  Bezier(12) = {15, 18, 19, 20, 21, 22, 16};    // lower wall along the stenosis
  Line(13) = {16, 17};                          // lower wall downstream
  Line(14) = {14, 1};                           // inflow, lower half
  Line(15) = {17, 4};                           // outflow, lower half
  Line(16) = {15, 2};                           // x = -length / 2 (interior)
  Line(17) = {16, 3};                           // x = length / 2 (interior)
  Transfinite Curve{11} = f * nx_upstream + 1 Using Progression 1 / q_upstream;
  Transfinite Curve{12} = f * n_throat + 1;
  Transfinite Curve{13} = f * nx_downstream + 1 Using Progression q_downstream;
  Transfinite Curve{14, 16, 17, 15} = f * ny + 1 Using Progression q_wall;
  Curve Loop(4) = {11, 16, -1, -14};
  Plane Surface(4) = {4};  // upstream, lower half
  Curve Loop(5) = {12, 17, -2, -16};
  Plane Surface(5) = {5};  // throat, lower half
  Curve Loop(6) = {13, 15, -3, -17};
  Plane Surface(6) = {6};  // downstream, lower half
  Transfinite Surface{4} = {14, 15, 2, 1};
  Transfinite Surface{5} = {15, 16, 3, 2};
  Transfinite Surface{6} = {16, 17, 4, 3};
  Recombine Surface{4:6};
EndIf

Physical Surface("fluid") = {1:3 + 3 * full};
If (full == 1)
  Physical Curve("inflow") = {4, 14};
  Physical Curve("outflow") = {5, 15};
  Physical Curve("lower_upstream_wall") = {11};
  Physical Curve("lower_stenosis") = {12};
  Physical Curve("lower_downstream_wall") = {13};
Else
  Physical Curve("inflow") = {4};
  Physical Curve("outflow") = {5};
  Physical Curve("symmetry") = {1, 2, 3};
EndIf
// the wall in three groups, so that a scene can ask for the force on the stenosis alone and for
// the recirculation behind it along the straight wall downstream (docs/geometries.md)
Physical Curve("upstream_wall") = {6};    // y = 1, x < -length / 2
Physical Curve("stenosis") = {7};         // the stenosed wall, |x| < length / 2
Physical Curve("downstream_wall") = {8};  // y = 1, x > length / 2

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 0;
Mesh.Smoothing = 0;
