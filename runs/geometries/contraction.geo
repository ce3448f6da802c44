// The 4:1 planar contraction of the viscoelastic benchmark (Alves, Oliveira & Pinho, J. Non-Newtonian
// Fluid Mech. 110 (2003) 45-75; docs/contraction.md): upstream half-width H1 = 4, downstream
// half-width H2 = 1 (lengths in H2), upper half only with the symmetry line y = 0. The contraction
// plane is x = 0, so the salient corner is (0, 4), the re-entrant corner (0, 1), and a vortex length
// measured along the upstream wall y = 4 is measured from x = 0.
//
// Four structured blocks, every grading a geometric progression with its finest element, of size
// `corner` on M1, at one of the corners:
//   lower    x in [-upstream_length, 0] by y in [0, 1]: fine towards x = 0 and towards y = 1
//   step     x in [-upstream_length, 0] by y in [1, 2.5]: fine towards x = 0 and towards y = 1
//   salient  x in [-upstream_length, 0] by y in [2.5, 4]: fine towards x = 0 and towards y = 4
//   outlet   x in [0, downstream_length] by y in [0, 1]: fine towards x = 0 and towards y = 1
// so that the elements at the re-entrant corner are corner x corner squares on every side of it on
// M1, and nearly so on finer meshes (0.0190 by 0.0182 on M2: the gradings' f-th roots differ).
//
// The meshes M1, M2, M3, ... are -setnumber f 1, 2, 4, ...: f multiplies every element count and
// takes the f-th root of every progression factor, so each element of M1 is split into f x f
// elements of M_f (nested meshes; for f = 2 every size is halved up to the factor sqrt(q) between
// the two halves, which tends to 1).

SetFactory("Built-in");

// Every tunable number: -setnumber NAME VALUE (gmsh program, or the arguments of gmsh::initialize)
// or gmsh::onelab::setNumber("NAME", {VALUE}) before opening the file overrides it.
DefineConstant[
  f = {1, Name "f"},                                   // refinement (M1, M2, M3 = f 1, 2, 4)
  upstream_length = {80, Name "upstream_length"},      // from the inflow to the contraction plane, in H2
  downstream_length = {50, Name "downstream_length"},  // from the contraction plane to the outflow, in H2
  corner = {0.04, Name "corner"},                      // the finest element's size on M1, at the corners, in H2
  nx_upstream = {30, Name "nx_upstream"},              // elements along the upstream channel on M1
  nx_downstream = {30, Name "nx_downstream"},          // elements along the downstream channel on M1
  ny_lower = {8, Name "ny_lower"},                     // elements across 0 < y < 1 on M1
  ny_step = {8, Name "ny_step"}                        // elements across each half of the step 1 < y < 4 on M1
];

H1 = 4;
H2 = 1;
ys = 0.5 * (H1 + H2);  // where the two gradings along the step meet
Lu = upstream_length;
Ld = downstream_length;

If (f < 1 || f != Round(f))
  Error("contraction.geo: f must be a whole number >= 1 (got %g)", f);
  Abort;
EndIf
If (nx_upstream < 1 || nx_downstream < 1 || ny_lower < 1 || ny_step < 1 ||
    nx_upstream != Round(nx_upstream) || nx_downstream != Round(nx_downstream) ||
    ny_lower != Round(ny_lower) || ny_step != Round(ny_step))
  Error("contraction.geo: nx_upstream, nx_downstream, ny_lower and ny_step must be whole numbers >= 1");
  Abort;
EndIf
If (Lu <= 0 || Ld <= 0 || corner <= 0)
  Error("contraction.geo: upstream_length, downstream_length and corner must be positive");
  Abort;
EndIf
If (corner * nx_upstream >= Lu || corner * nx_downstream >= Ld || corner * ny_lower >= H2 ||
    corner * ny_step >= ys - H2)
  Error("contraction.geo: corner = %g is too coarse: corner times the element count must stay below the side's length (grading towards the corner)", corner);
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

// factors on M1, then their f-th roots: M_f nests M1
pn = nx_upstream;
pL = Lu;
ph = corner;
Call Progression;
q_upstream = pq^(1 / f);
pn = nx_downstream;
pL = Ld;
Call Progression;
q_downstream = pq^(1 / f);
pn = ny_lower;
pL = H2;
Call Progression;
q_lower = pq^(1 / f);
pn = ny_step;
pL = ys - H2;
Call Progression;
q_step = pq^(1 / f);

Point(1) = {-Lu, 0, 0};
Point(2) = {0, 0, 0};
Point(3) = {Ld, 0, 0};
Point(4) = {-Lu, H2, 0};
Point(5) = {0, H2, 0};  // the re-entrant corner
Point(6) = {Ld, H2, 0};
Point(7) = {-Lu, ys, 0};
Point(8) = {0, ys, 0};
Point(9) = {-Lu, H1, 0};
Point(10) = {0, H1, 0};  // the salient corner

Line(1) = {1, 2};    // symmetry, upstream
Line(2) = {2, 3};    // symmetry, downstream
Line(3) = {1, 4};    // inflow
Line(4) = {4, 7};    // inflow
Line(5) = {7, 9};    // inflow
Line(6) = {3, 6};    // outflow
Line(7) = {5, 6};    // downstream wall
Line(8) = {5, 8};    // step
Line(9) = {8, 10};   // step
Line(10) = {9, 10};  // upstream wall
Line(11) = {4, 5};   // y = H2 upstream (interior)
Line(12) = {7, 8};   // y = ys (interior)
Line(13) = {2, 5};   // x = 0 below the corner (interior)

Transfinite Curve{1, 11, 12, 10} = f * nx_upstream + 1 Using Progression 1 / q_upstream;
Transfinite Curve{2, 7} = f * nx_downstream + 1 Using Progression q_downstream;
Transfinite Curve{3, 13, 6} = f * ny_lower + 1 Using Progression 1 / q_lower;
Transfinite Curve{4, 8} = f * ny_step + 1 Using Progression q_step;
Transfinite Curve{5, 9} = f * ny_step + 1 Using Progression 1 / q_step;

Curve Loop(1) = {1, 13, -11, -3};
Plane Surface(1) = {1};  // lower
Curve Loop(2) = {11, 8, -12, -4};
Plane Surface(2) = {2};  // step
Curve Loop(3) = {12, 9, -10, -5};
Plane Surface(3) = {3};  // salient
Curve Loop(4) = {2, 6, -7, -13};
Plane Surface(4) = {4};  // outlet

Transfinite Surface{1} = {1, 2, 5, 4};
Transfinite Surface{2} = {4, 5, 8, 7};
Transfinite Surface{3} = {7, 8, 10, 9};
Transfinite Surface{4} = {2, 3, 6, 5};
Recombine Surface{1:4};

Physical Surface("fluid") = {1:4};
Physical Curve("inflow") = {3, 4, 5};
Physical Curve("outflow") = {6};
Physical Curve("symmetry") = {1, 2};
Physical Curve("upstream_wall") = {10};
Physical Curve("step") = {8, 9};
Physical Curve("downstream_wall") = {7};

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 0;
Mesh.Smoothing = 0;
