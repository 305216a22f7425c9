// SPDX-License-Identifier: MIT
#include "core/io/mesh_text_scanner.h"

#include <cmath>

#include <doctest/doctest.h>

#include "tests/unit/io/io_test_util.h"

using namespace volspline::io;
using volspline::io::test::error_of;
using volspline::io::test::has;

TEST_CASE("scanner: lines, tokens, comments and line numbers") {
  MeshTextScanner scan("a b\r\n\n# c\n  d  # e\nf", "s.txt");
  std::string_view token;
  REQUIRE(scan.next_content_line());
  CHECK(scan.line_number() == 1);
  CHECK((scan.next_token(token) && token == "a"));
  CHECK((scan.next_token(token) && token == "b"));
  CHECK(!scan.next_token(token));
  REQUIRE(scan.next_content_line());
  CHECK(scan.line_number() == 4);
  CHECK((scan.next_token(token) && token == "d"));
  CHECK(scan.line_done());
  CHECK((scan.next_token_any_line(token) && token == "f"));
  CHECK(scan.line_number() == 5);
  CHECK(!scan.next_token_any_line(token));
}

TEST_CASE("scanner: numbers parse exactly, bad ones throw with file and line") {
  double value = 0;
  CHECK((parse_double_token("0.1", value) && value == 0.1));
  CHECK((parse_double_token("+2.5e-3", value) && value == 2.5e-3));
  CHECK((parse_double_token("1e400", value) && std::isinf(value)));
  CHECK((parse_double_token("1e-400", value) && value == 0.0));
  CHECK(!parse_double_token("1.0x", value));
  CHECK(!parse_double_token("", value));
  std::int64_t n = 0;
  CHECK((parse_int_token("-12", n) && n == -12));
  CHECK(!parse_int_token("1.5", n));
  CHECK(!parse_int_token("99999999999999999999", n));

  MeshTextScanner scan("\n1 nan inf x\n", "n.txt");
  scan.next_content_line();
  CHECK(scan.read_double("a") == 1.0);
  CHECK(has(error_of([&] { scan.read_double("b"); }), "n.txt:2: NaN b"));
  CHECK(has(error_of([&] { scan.read_double("c"); }), "n.txt:2: infinite c"));
  CHECK(has(error_of([&] { scan.read_int("d"); }), "n.txt:2: bad d 'x'"));
  CHECK(has(error_of([&] { scan.read_int("e"); }), "n.txt:2: missing e"));
}
