// Every mesh keller cannot use and every file it cannot read (core/GmshMesh), each refused with a
// message that names the file, the element or group and what to change.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <thread>

#include <filesystem>

#include <tuple>

#include "core/GmshMesh.hpp"
#include "core/GmshProcess.hpp"
#include "support/GmshTestMeshes.hpp"

using namespace keller;
using namespace keller::test;

// A clockwise element among counter-clockwise ones in one surface is inverted; all of them
// clockwise is a reversed surface, read counter-clockwise.
TEST_F(GmshMeshTest, InvertedElementIsRefusedAndAReversedSurfaceIsNot) {
  BoxMesh box;
  box.box(0, 1, 0, 1);
  box.box(1, 2, 0, 1);
  const std::array<int, 9> swap = {0, 3, 6, 1, 4, 7, 2, 5, 8};
  auto mirrored = [&](std::array<int, 9> el) {
    std::array<int, 9> out{};
    for (int a = 0; a < 9; ++a) out[a] = el[swap[a]];
    return out;
  };
  BoxMesh one = box;
  one.elements[1] = mirrored(box.elements[1]);
  write_gmsh_mesh(one.mesh(outer_edges(one.elements)), path("inverted.msh"));
  const std::string message = refusal(path("inverted.msh"));
  EXPECT_NE(message.find(path("inverted.msh")), std::string::npos) << message;
  EXPECT_NE(message.find("element 2 (Gmsh surface 1"), std::string::npos) << message;
  EXPECT_NE(message.find("is inverted"), std::string::npos) << message;

  BoxMesh all = box;
  for (auto& el : all.elements) el = mirrored(el);
  write_gmsh_mesh(all.mesh(outer_edges(all.elements)), path("reversed.msh"));
  const Mesh m = read_gmsh_mesh(path("reversed.msh"));
  EXPECT_GT(m.jacobian_range().first, 0.0);
  EXPECT_NEAR(area(m), 2.0, 1e-14);
  EXPECT_NEAR(length(m, "wall"), 6.0, 1e-14);
}

// An element whose det J changes sign inside it: its centre node pulled past a corner.
TEST_F(GmshMeshTest, DegenerateElementIsRefused) {
  BoxMesh box;
  box.box(0, 1, 0, 1);
  box.nodes[box.elements[0][4]] = {1.4, 1.4};
  write_gmsh_mesh(box.mesh(outer_edges(box.elements)), path("folded.msh"));
  const std::string message = refusal(path("folded.msh"));
  EXPECT_NE(message.find(path("folded.msh")), std::string::npos) << message;
  EXPECT_NE(message.find("element 1 (Gmsh surface 1"), std::string::npos) << message;
  EXPECT_NE(message.find("degenerate or folded"), std::string::npos) << message;
}

// A hanging node: one element on the left, two on the right sharing the left one's side.
TEST_F(GmshMeshTest, HangingNodeIsRefused) {
  BoxMesh box;
  box.box(0, 2, 0, 2);
  box.box(2, 3, 0, 1);
  box.box(2, 3, 1, 2);
  write_gmsh_mesh(box.mesh(outer_edges(box.elements)), path("hanging.msh"));
  const std::string message = refusal(path("hanging.msh"));
  EXPECT_NE(message.find(path("hanging.msh")), std::string::npos) << message;
  EXPECT_NE(message.find("not conforming"), std::string::npos) << message;
  EXPECT_NE(message.find("on the edge of element 1 from (2, 0) to (2, 2)"), std::string::npos) << message;
}

// Two squares meshed apart: their common side has two copies of its nodes (an inner boundary).
TEST_F(GmshMeshTest, SurfacesNotSharingTheirCurveAreRefused) {
  BoxMesh left, right;
  left.box(0, 1, 0, 1);
  right.box(1, 2, 0, 1);
  std::vector<Mesh::Point> nodes = left.nodes;
  std::vector<std::array<int, 9>> elements = left.elements;
  for (auto el : right.elements) {
    for (int& n : el) n += static_cast<int>(left.nodes.size());
    elements.push_back(el);
  }
  nodes.insert(nodes.end(), right.nodes.begin(), right.nodes.end());
  write_gmsh_mesh(Mesh(nodes, elements, {0, 0}, {"fluid"}, outer_edges(elements), {}), path("apart.msh"));
  const std::string message = refusal(path("apart.msh"));
  EXPECT_NE(message.find("not conforming"), std::string::npos) << message;
  EXPECT_NE(message.find("sharing the curve"), std::string::npos) << message;
}

// Three elements on one edge; two elements on the same corners of an edge with different middles.
TEST_F(GmshMeshTest, OverlappingElementsAreRefused) {
  BoxMesh box;
  box.box(0, 1, 0, 1);
  box.box(1, 2, 0, 1);
  box.box(1, 2, 0, 1);
  write_gmsh_mesh(box.mesh(outer_edges(box.elements)), path("three.msh"));
  const std::string message = refusal(path("three.msh"));
  EXPECT_NE(message.find("belongs to 3 elements (1, 2, 3"), std::string::npos) << message;

  BoxMesh pair;
  pair.box(0, 1, 0, 1);
  pair.box(1, 2, 0, 1);
  pair.nodes.push_back({1.05, 0.5});  // the right element's own middle node on the shared edge
  pair.elements[1][3] = static_cast<int>(pair.nodes.size()) - 1;
  write_gmsh_mesh(pair.mesh(outer_edges(pair.elements)), path("middle.msh"));
  const std::string middle = refusal(path("middle.msh"));
  EXPECT_NE(middle.find("elements 1 and 2 share the ends (1, 0) and (1, 1) of an edge but not its middle node"),
            std::string::npos)
      << middle;
}

// Every outer edge must be named; a named line must be an element edge.
TEST_F(GmshMeshTest, UnnamedOuterEdgeIsRefusedWithItsPlace) {
  Msh22 m = single_quad({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  m.elements.erase(m.elements.begin() + 3);  // the left side's line
  const std::string file = write_file(path("unnamed.msh"), m.text());
  const std::string message = refusal(file);
  EXPECT_NE(message.find(file), std::string::npos) << message;
  EXPECT_NE(
      message.find(
          "the edge of element 4 from (0, 0) to (0, 1) is on the boundary of the domain but in no 1D physical group"),
      std::string::npos)
      << message;
  EXPECT_NE(message.find("Physical Curve"), std::string::npos) << message;
}

TEST_F(GmshMeshTest, LineThatIsNoElementEdgeIsRefused) {
  Msh22 m = single_quad({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  m.names.emplace_back(1, 6, "diagonal");
  m.elements.push_back({8, 6, 5, {1, 3, 9}});  // corner to corner through the centre
  const std::string message = refusal(write_file(path("diagonal.msh"), m.text()));
  EXPECT_NE(message.find("line element 6 of physical curve 'diagonal' (from (0, 0) to (1, 1)) is not an edge"),
            std::string::npos)
      << message;

  Msh22 off = single_quad({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  off.nodes.push_back({5, 5});
  off.nodes.push_back({6, 6});
  off.names.emplace_back(1, 6, "far");
  off.elements.push_back({8, 6, 5, {10, 11, 9}});
  const std::string far = refusal(write_file(path("far.msh"), off.text()));
  EXPECT_NE(
      far.find("line element 6 of physical curve 'far' (Gmsh curve 5) is not an edge of the 2D elements: its node 10"),
      std::string::npos)
      << far;
}

// 2D elements other than 9-node quadrilaterals, each with what to change in the .geo.
TEST_F(GmshMeshTest, ElementsOtherThanNineNodeQuadrilateralsAreRefused) {
  const std::string recombine = "Recombine Surface{1};\n";
  const std::vector<std::tuple<std::string, std::string, std::string, std::string>> cases = {
      {"triangles3.geo", replace(replace(kRectangleGeo, recombine, ""), "Mesh.ElementOrder = 2;", ""), "Triangle 3",
       "Recombine Surface"},
      {"triangles6.geo", replace(kRectangleGeo, recombine, ""), "Triangle 6", "Recombine Surface"},
      {"quads4.geo", replace(kRectangleGeo, "Mesh.ElementOrder = 2;", ""), "Quadrilateral 4", "Mesh.ElementOrder = 2;"},
      {"quads8.geo", replace(kRectangleGeo, "Mesh.SecondOrderIncomplete = 0;", "Mesh.SecondOrderIncomplete = 1;"),
       "Quadrilateral 8", "Mesh.SecondOrderIncomplete = 0;"},
  };
  for (const auto& [name, geo, type, fix] : cases) {
    const std::string file = write_file(path(name), geo);
    const std::string message = refusal(file);
    EXPECT_EQ(message.rfind(file + ": element ", 0), 0u) << message;
    EXPECT_NE(message.find(" of physical surface 'fluid' is a " + type + " (Gmsh element type"), std::string::npos)
        << message;
    EXPECT_NE(message.find(fix), std::string::npos) << message;
  }
}

// 1D elements of a physical curve other than 3-node lines.
TEST_F(GmshMeshTest, BoundaryLinesOtherThanThreeNodeLinesAreRefused) {
  Msh22 m = single_quad({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  m.elements[0] = {1, 1, 1, {1, 2}};  // a 2-node line in "bottom"
  const std::string message = refusal(write_file(path("line2.msh"), m.text()));
  EXPECT_NE(message.find("element 1 of physical curve 'bottom' is a Line 2 (Gmsh element type 1, 2 nodes); keller "
                         "needs 3-node lines"),
            std::string::npos)
      << message;
}

TEST_F(GmshMeshTest, PhysicalGroupsMustExistAndBeNamed) {
  Msh22 none = single_quad({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  none.elements.back().physical = 0;  // the quadrilateral in no physical surface
  none.names.pop_back();
  const std::string file = write_file(path("nogroup.msh"), none.text());
  EXPECT_NE(refusal(file).find(file + ": no 2D physical group"), std::string::npos) << refusal(file);

  Msh22 unnamed = single_quad({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  unnamed.names.pop_back();
  const std::string message = refusal(write_file(path("unnamedgroup.msh"), unnamed.text()));
  EXPECT_NE(message.find("physical surface 5 has no name"), std::string::npos) << message;

  const std::string two =
      write_file(path("twogroups.geo"), kRectangleGeo + std::string("Physical Surface(\"solid\") = {1};\n"));
  const std::string twice = refusal(two);
  EXPECT_EQ(twice.rfind(two + ": element ", 0), 0u) << twice;
  EXPECT_NE(twice.find(" is in two physical surfaces, 'fluid' and 'solid'"), std::string::npos) << twice;
}

// Files Gmsh cannot read, or that hold no 2D mesh: a MeshFileError with Gmsh's own message and the
// file's name, nothing on keller's standard output, and Gmsh still reads a good file afterwards.
TEST_F(GmshMeshTest, DamagedFilesAreRefusedWithGmshsMessage) {
  const std::string good = write_file(path("rectangle.geo"), kRectangleGeo);
  write_gmsh_mesh(read_gmsh_mesh(good), path("good.msh"));
  const std::string whole = test::file_contents(path("good.msh"));
  // 3000 pseudo-random bytes (an LCG): in one process, with Gmsh's default General.AbortOnError = 2,
  // Gmsh 4.8.4 throws out of its parser on these and fails on the good .geo read next (each read
  // now runs in a child of its own, and keller sets AbortOnError = 0)
  std::string garbage(3000, '\0');
  unsigned long x = 1;
  for (char& byte : garbage) {
    x = (x * 1103515245 + 12345) % 2147483648;
    byte = static_cast<char>((x >> 16) & 255);
  }
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"truncated.msh", whole.substr(0, whole.size() / 2), "Gmsh reported an error while reading it"},
      {"garbage.msh", garbage, "Gmsh reported an error while reading it"},
      {"empty.msh", "", "no 2D physical group"},
      {"syntax.geo", "Point(1) = {0, 0, 0;\n",
       "Gmsh reported an error while reading it:\n  '" + path("syntax.geo") + "', line 1: syntax error"},
      {"lines.geo", "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Line(1) = {1, 2}; Physical Curve(\"wall\") = {1};\n",
       "no 2D physical group"},
  };
  testing::internal::CaptureStdout();
  for (const auto& [name, text, expected] : cases) {
    const std::string file = write_file(path(name), text);
    const std::string message = refusal(file);
    EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_NEAR(area(read_gmsh_mesh(good)), 3.0, 1e-13) << "after " << name;
  }
  const std::string missing = refusal(path("missing.msh"));
  EXPECT_EQ(missing, path("missing.msh") + ": cannot be read (no such file, or no permission)");
  EXPECT_NE(refusal(path("rectangle.txt")).find("give a mesh (.msh) or a geometry (.geo)"), std::string::npos);
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
}

// keller's meshes lie in z = 0 (to 1e-12 of their size).
TEST_F(GmshMeshTest, NodeOffThePlaneIsRefused) {
  std::string text = single_quad({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}).text();
  const auto line = text.find("\n7 ");
  text.replace(text.find('\n', line + 1) - 1, 1, "0.5");  // node 7's z
  const std::string file = write_file(path("plane.msh"), text);
  const std::string message = refusal(file);
  EXPECT_EQ(message, file +
                         ": node 7 is at z = 0.5 off the plane z = 0; keller's meshes are plane: in the .geo, put "
                         "every point at z = 0");
}

// Gmsh 4.8.4 crashes (a segmentation fault in its reader) on a format-2.2 element naming the node
// one past the last. Gmsh runs in a child process: keller refuses the file and goes on.
TEST_F(GmshMeshTest, FileThatCrashesGmshIsRefused) {
  Msh22 m = single_quad({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  m.elements.back().nodes[8] = 10;
  const std::string file = write_file(path("crash.msh"), m.text());
  const std::string message = refusal(file);
  // signal 11 (under the sanitizers of .ci/sanitize, their report ends the child with signal 6)
  EXPECT_EQ(message.rfind(file + ": Gmsh crashed while reading it (signal ", 0), 0u) << message;
  EXPECT_NEAR(area(read_gmsh_mesh(write_file(path("rectangle.geo"), kRectangleGeo))), 3.0, 1e-13);
}

// A .geo that stops itself (a parameter out of its range: Error, then Abort) ends Gmsh with
// SIGABRT; the refusal says Gmsh's own error line, not that Gmsh crashed on a damaged file.
TEST_F(GmshMeshTest, AGeoThatStopsItselfIsRefusedWithItsOwnMessage) {
  const std::string file =
      write_file(path("ratio.geo"),
                 "DefineConstant[ ratio = 4 ];\n"
                 "If (ratio <= 1)\n  Error(\"the contraction ratio must be above 1, not %g\", ratio);\n"
                 "  Abort;\nEndIf\n");
  const std::string message = refusal(file, GmshOptions{.geo_parameters = {{"ratio", 0.5}}});
  EXPECT_EQ(message.rfind(file + ": Gmsh stopped while reading it, with errors:\n  ", 0), 0u) << message;
  EXPECT_NE(message.find("the contraction ratio must be above 1, not 0.5"), std::string::npos) << message;
  EXPECT_EQ(message.find("crashed"), std::string::npos) << message;
}

// A damaged node count: Gmsh would take 4.7 GB of memory for 5 s (measured, without a limit) before
// it finds the file short. The child's data is capped from the file's size (2 GB + 1000 bytes per
// byte), so it stops at once; no child of this test process ever needed 1 GB.
TEST_F(GmshMeshTest, DamagedCountIsRefusedWithoutTheMachinesMemory) {
  const std::string file = write_file(path("count.msh"),
                                      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 200000000 1 200000000\n"
                                      "2 1 0 200000000\n1\n0 0 0\n$EndNodes\n");
  const std::string message = refusal(file);
  // Gmsh reports the failed allocation (under the sanitizers their allocator aborts the child)
  EXPECT_EQ(message.rfind(file + ": Gmsh ", 0), 0u) << message;
  EXPECT_NE(message.find(" while reading it"), std::string::npos) << message;
  rusage children{};
  ASSERT_EQ(getrusage(RUSAGE_CHILDREN, &children), 0);
  EXPECT_LT(children.ru_maxrss, 1024L * 1024L);  // kilobytes
}

// Writing where no file can be: refused with the file's name, nothing left behind.
TEST_F(GmshMeshTest, UnwritableTargetIsRefused) {
  BoxMesh box;
  box.box(0, 1, 0, 1);
  const std::string target = path("no_such_folder/mesh.msh");
  try {
    write_gmsh_mesh(box.mesh(outer_edges(box.elements)), target);
    ADD_FAILURE() << "written";
  } catch (const MeshFileError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(target + ": cannot be written", 0), 0u) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path("no_such_folder")));
}

// A child that never answers (as Gmsh looping on a damaged file) is stopped by an interrupt: it
// takes SIGINT's default action, whatever keller's handler, and the read is reported interrupted.
TEST_F(GmshMeshTest, InterruptedChildIsReported) {
  const std::string pid_file = path("child.pid");
  std::atomic<bool> done{false};
  std::thread interrupt([&] {
    for (int k = 0; k < 500 && test::file_contents(pid_file).empty(); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const pid_t child = std::stoi(test::file_contents(pid_file));
    ::kill(child, SIGINT);
    for (int k = 0; k < 500 && !done; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!done) ::kill(child, SIGKILL);  // the interrupt did not stop it: fail rather than hang
  });
  struct sigaction ignore {
  }, old{};
  ignore.sa_handler = [](int) {};  // keller's own handler only notes the request
  sigaction(SIGINT, &ignore, &old);
  std::string message;
  try {
    run_gmsh_child("loop.msh", "reading", 0, [&]() -> std::string {
      write_file(pid_file, std::to_string(::getpid()));
      for (;;) ::pause();
    });
  } catch (const MeshFileError& e) {
    message = e.what();
  }
  done = true;
  interrupt.join();
  sigaction(SIGINT, &old, nullptr);
  EXPECT_EQ(message, "loop.msh: Gmsh was interrupted while reading it");
}
