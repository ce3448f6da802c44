// The confined cylinder of keller's built-in `cylinder` problem (docs/cylinder.md): a cylinder of
// radius 1 centred at the origin in a channel of half-width 2, upper half only (symmetry line
// y = 0), inflow at x = -upstream_length, outflow at x = downstream_length. Five structured blocks
// as build_cylinder_mesh (problems/cylinder/CylinderProblem.cpp) makes them, with the same element
// counts and gradings:
//   upstream    12 f along x (fine next to x = -2, upstream_ratio) by 8 f across (uniform)
//   west        8 f around the arc pi..3pi/4 by 8 f radially (fine at the cylinder, radial_ratio)
//   north       16 f around 3pi/4..pi/4 by 8 f radially
//   east        8 f radially by n_rear around 0..pi/4 (fine at the rear stagnation point on the
//               arc, rear_ratio; fine at the axis on x = 2, wake_ratio)
//   downstream  24 f along x (fine next to x = 2, downstream_ratio) by n_rear across (wake_ratio)
// with n_rear = rear_per_f * f. The presets: C<f> is the default with f = <f>; W<f> adds
// -setnumber rear_per_f 16 -setnumber rear_ratio 4 -setnumber wake_ratio 20.
//
// A ratio is largest / smallest element of a side; keller's geometric grading has sizes h q^i,
// i = 0..n-1, so q = ratio^(1/(n-1)), which is Gmsh's `Progression` factor along the curve's
// direction (1/q where the curve runs from the coarse end to the fine one).
//
// The blocks around the cylinder are Coons surfaces (`Surface`, not `Plane Surface`): their
// parametrisation is the transfinite blend of the arc and the box side that keller's blocks use,
// and their mid-side and centre nodes sit at the parametric midpoints, as keller's do (the east
// block of a W mesh is the exception, see there). runs/geometries/check_geometries.py compares
// every node with keller's formulas: C<f> to 1e-7 (Gmsh's placement of graded vertices along the
// channel's long sides; 3e-9 around the cylinder), W<f> the same at the vertices.

SetFactory("Built-in");

// Every tunable number: -setnumber NAME VALUE (gmsh program, or the arguments of gmsh::initialize)
// or gmsh::onelab::setNumber("NAME", {VALUE}) before opening the file overrides it.
DefineConstant[
  f = {1, Name "f"},                                   // refinement of C1 (C<f>, W<f>)
  rear_per_f = {8, Name "rear_per_f"},                 // elements around the rear eighth per f (8: C, 16: W)
  upstream_length = {20, Name "upstream_length"},      // inflow to the cylinder's centre
  downstream_length = {30, Name "downstream_length"},  // cylinder's centre to the outflow
  radial_ratio = {4, Name "radial_ratio"},             // largest / smallest radial element
  upstream_ratio = {10, Name "upstream_ratio"},        // largest / smallest upstream element
  downstream_ratio = {20, Name "downstream_ratio"},    // largest / smallest downstream element
  wake_ratio = {1, Name "wake_ratio"},                 // largest / smallest across the channel behind the cylinder
  rear_ratio = {1, Name "rear_ratio"}                  // largest / smallest around the rear eighth
];

If (f < 1 || f != Round(f) || rear_per_f < 1 || rear_per_f != Round(rear_per_f))
  Error("cylinder.geo: f and rear_per_f must be whole numbers >= 1 (got f = %g, rear_per_f = %g)", f, rear_per_f);
  Abort;
EndIf
If (upstream_length <= 2 || downstream_length <= 2)
  Error("cylinder.geo: upstream_length and downstream_length must exceed 2, the half-width of the box around the cylinder");
  Abort;
EndIf
If (radial_ratio < 1 || upstream_ratio < 1 || downstream_ratio < 1 || wake_ratio < 1 || rear_ratio < 1)
  Error("cylinder.geo: every *_ratio is largest / smallest element and must be >= 1");
  Abort;
EndIf

n_quarter = 8 * f;
n_radial = 8 * f;
nx_upstream = 12 * f;
nx_downstream = 24 * f;
n_rear = rear_per_f * f;

// progression factor of n elements whose largest / smallest is ratio: ratio^(1/(n-1)) (any
// factor for a single element)
q_radial = radial_ratio^(1 / Max(n_radial - 1, 1));
q_upstream = upstream_ratio^(1 / Max(nx_upstream - 1, 1));
q_downstream = downstream_ratio^(1 / Max(nx_downstream - 1, 1));
q_wake = wake_ratio^(1 / Max(n_rear - 1, 1));
q_rear = rear_ratio^(1 / Max(n_rear - 1, 1));

Lu = upstream_length;
Ld = downstream_length;
c = Sqrt(0.5);

Point(1) = {-Lu, 0, 0};
Point(2) = {-2, 0, 0};
Point(3) = {-1, 0, 0};
Point(4) = {0, 0, 0};  // centre of the arcs
Point(5) = {1, 0, 0};
Point(6) = {2, 0, 0};
Point(7) = {Ld, 0, 0};
Point(8) = {-Lu, 2, 0};
Point(9) = {-2, 2, 0};
Point(10) = {2, 2, 0};
Point(11) = {Ld, 2, 0};
Point(12) = {-c, c, 0};  // the cylinder at 3pi/4
Point(13) = {c, c, 0};   // the cylinder at pi/4

// symmetry line y = 0
Line(1) = {1, 2};  // upstream, runs towards the box
Line(2) = {3, 2};  // west radial, from the cylinder outwards
Line(3) = {5, 6};  // east radial, from the cylinder outwards
Line(4) = {6, 7};  // downstream
// wall y = 2
Line(5) = {8, 9};
Line(6) = {9, 10};
Line(7) = {10, 11};
// inflow and outflow
Line(8) = {1, 8};
Line(9) = {7, 11};
// block interfaces
Line(10) = {2, 9};   // x = -2
Line(11) = {12, 9};  // radial at 3pi/4
Line(12) = {13, 10}; // radial at pi/4
Line(13) = {6, 10};  // x = 2
// the cylinder
Circle(14) = {3, 4, 12};  // pi .. 3pi/4
Circle(15) = {12, 4, 13}; // 3pi/4 .. pi/4
Circle(16) = {5, 4, 13};  // 0 .. pi/4

Transfinite Curve{1, 5} = nx_upstream + 1 Using Progression 1 / q_upstream;
Transfinite Curve{8, 10, 14} = n_quarter + 1;
Transfinite Curve{6, 15} = 2 * n_quarter + 1;
Transfinite Curve{2, 3, 11, 12} = n_radial + 1 Using Progression q_radial;
Transfinite Curve{16} = n_rear + 1 Using Progression q_rear;
Transfinite Curve{13, 9} = n_rear + 1 Using Progression q_wake;
Transfinite Curve{4, 7} = nx_downstream + 1 Using Progression q_downstream;

Curve Loop(1) = {1, 10, -5, -8};
Plane Surface(1) = {1};  // upstream
Curve Loop(2) = {14, 11, -10, -2};
Surface(2) = {2};  // west
Curve Loop(3) = {15, 12, -6, -11};
Surface(3) = {3};  // north
Curve Loop(4) = {3, 13, -12, -16};
// east: with a graded wake (W) keller's vertices (1 - r) arc(theta_j) + r (2, y_j) pair the arc's
// rear grading with the wake grading of x = 2, which a Coons surface interpolates in its parameters
// (vertices off by up to 0.04); a plane surface's transfinite interpolation in x, y reproduces them
// exactly, its mid-side nodes then sit on straight interior edges (keller's are curved: O(h^2) apart)
If (wake_ratio == 1 && rear_ratio == 1)
  Surface(4) = {4};
Else
  Plane Surface(4) = {4};
EndIf
Curve Loop(5) = {4, 9, -7, -13};
Plane Surface(5) = {5};  // downstream

Transfinite Surface{1} = {1, 2, 9, 8};
Transfinite Surface{2} = {3, 12, 9, 2};
Transfinite Surface{3} = {12, 13, 10, 9};
Transfinite Surface{4} = {5, 6, 10, 13};
Transfinite Surface{5} = {6, 7, 11, 10};
Recombine Surface{1:5};

Physical Surface("fluid") = {1:5};
Physical Curve("inflow") = {8};
Physical Curve("outflow") = {9};
Physical Curve("wall") = {5, 6, 7};
Physical Curve("symmetry") = {1, 2, 3, 4};
Physical Curve("cylinder") = {14, 15, 16};

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 0;
Mesh.Smoothing = 0;
Mesh.LcIntegrationPrecision = 1e-14;
