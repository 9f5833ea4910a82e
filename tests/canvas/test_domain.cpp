#include <gtest/gtest.h>

#include "implicit_shapes.h"
#include "rvor/domain.h"
#include "rvor/error.h"
#include "rvor/spec_text.h"

namespace rvor {
namespace {

std::string error_of(const std::string& spec) {
  try {
    parse_domain(spec);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(ParseDomain, Box) {
  const DomainSpec d = parse_domain("box:-1,0,0.5,1,2,3");
  EXPECT_EQ(d.kind, DomainSpec::Kind::Box);
  EXPECT_EQ(d.dimension(), 3);
  EXPECT_EQ(d.bounds.lo, Vec3(-1, 0, 0.5));
  EXPECT_EQ(d.bounds.hi, Vec3(1, 2, 3));
  EXPECT_EQ(d.description(), "box:-1,0,0.5,1,2,3");
}

TEST(ParseDomain, Rectangle) {
  const DomainSpec d = parse_domain("rect:0,0,2,1");
  EXPECT_EQ(d.kind, DomainSpec::Kind::Rectangle);
  EXPECT_EQ(d.dimension(), 2);
  EXPECT_EQ(d.bounds.lo, Vec3(0, 0, 0));
  EXPECT_EQ(d.bounds.hi, Vec3(2, 1, 0));
  EXPECT_EQ(d.description(), "rect:0,0,2,1");
}

// Numbers are written back with the digits they need: with 10, a domain 1e14 from the origin and
// 1e3 wide read as one of zero width.
TEST(ParseDomain, DescriptionsKeepTheDigitsTheyNeed) {
  EXPECT_EQ(parse_domain("rect:1e14,1e14,1.00000000001e14,1.00000000001e14").description(),
            "rect:1e+14,1e+14,100000000001000,100000000001000");
  EXPECT_EQ(parse_domain("box:-0.1,0.2,0.3,1.5,2,3").description(), "box:-0.1,0.2,0.3,1.5,2,3");
  EXPECT_EQ(format_spec_number(1e-310), "1e-310");  // a subnormal: std::stod would throw
}

TEST(ParseDomain, Mesh) {
  const DomainSpec d = parse_domain("mesh:some/dir/part.STL");
  EXPECT_EQ(d.kind, DomainSpec::Kind::Mesh);
  EXPECT_EQ(d.path, "some/dir/part.STL");
  EXPECT_EQ(d.dimension(), 3);
  EXPECT_EQ(d.description(), "mesh:some/dir/part.STL");
}

TEST(ParseDomain, ImplicitShapes) {
  const DomainSpec sphere = parse_domain("implicit:sphere:center=1,2,3,r=0.5");
  EXPECT_EQ(sphere.kind, DomainSpec::Kind::Implicit);
  EXPECT_FALSE(sphere.implicit_is_2d());
  EXPECT_EQ(sphere.dimension(), 3);
  EXPECT_EQ(sphere.bounds.lo, Vec3(0.5, 1.5, 2.5));
  EXPECT_EQ(sphere.description(), "implicit:sphere:center=1,2,3,r=0.5");

  const DomainSpec disk = parse_domain("implicit:disk:r=2");
  EXPECT_TRUE(disk.implicit_is_2d());
  EXPECT_EQ(disk.dimension(), 2);
  EXPECT_EQ(disk.bounds.hi, Vec3(2, 2, 0));

  const DomainSpec torus = parse_domain("implicit:torus:R=2,r=0.5");
  EXPECT_EQ(torus.bounds.hi, Vec3(2.5, 2.5, 0.5));
  const DomainSpec ellipsoid = parse_domain("implicit:ellipsoid:a=3,b=2,c=1");
  EXPECT_EQ(ellipsoid.bounds.lo, Vec3(-3, -2, -1));
  EXPECT_EQ(parse_domain("implicit:sphere").description(), "implicit:sphere:center=0,0,0,r=1");
}

// Blanks around numbers and parameters are taken as metric specs take them: "rect: -1, -1, 1, 1"
// was refused with "' -1' is not a finite number".
TEST(ParseDomain, BlanksAroundItemsAreTakenAsInMetricSpecs) {
  EXPECT_EQ(parse_domain("rect: -1, -1,\t1, 1 ").description(), "rect:-1,-1,1,1");
  EXPECT_EQ(parse_domain("box:0, 0, 0, 1, 2, 3").description(), "box:0,0,0,1,2,3");
  EXPECT_EQ(parse_domain("implicit:sphere: center = 1, 2, 3, r = 0.5").description(),
            "implicit:sphere:center=1,2,3,r=0.5");
  EXPECT_THROW(parse_domain("rect:0, ,1,1"), Error);  // an item of blanks is still empty
}

TEST(ParseDomain, MalformedSpecsNameTheSpec) {
  for (const std::string spec : {"box:0,0,0,1,1",
                                 "box:0,0,0,1,1,x",
                                 "box:0,0,0,0,1,1",
                                 "rect:0,0,1",
                                 "rect:0,1,1,0",
                                 "cube:0,0,1,1",
                                 "box",
                                 "mesh:",
                                 "mesh:shape.ply",
                                 "implicit:cube",
                                 "implicit:sphere:r=-1",
                                 "implicit:sphere:radius=1",
                                 "implicit:sphere:center=1,2",
                                 "implicit:sphere:r=1,r=2",
                                 "implicit:disk:center=1,2,3",
                                 "implicit:sphere:5",
                                 "rect:0,0,1,1,",
                                 "rect:0,,1,1",
                                 "rect:0x0,0,1,1",
                                 "rect:0,0,1,inf",
                                 "rect:0,0,1,1e999",
                                 "implicit:sphere:r=1,",
                                 "implicit:sphere:r=0x1",
                                 "implicit:sphere:r=+-1"}) {
    const std::string message = error_of(spec);
    EXPECT_NE(message.find(spec), std::string::npos) << spec << " -> '" << message << "'";
  }
}

TEST(SpecText, DecimalsOnlyWholeAndFinite) {
  EXPECT_EQ(parse_decimal("1"), 1.0);
  EXPECT_EQ(parse_decimal("-2.5"), -2.5);
  EXPECT_EQ(parse_decimal("+3e-4"), 3e-4);
  EXPECT_EQ(parse_decimal(".5"), 0.5);
  for (const char* text : {"", "+", "-", " 1", "1 ", "0x10", "1,5", "inf", "nan", "-nan", "1e999",
                           "+-1", "--1", "1.2.3", "e5"})
    EXPECT_FALSE(parse_decimal(text).has_value()) << "'" << text << "'";
}

TEST(SpecText, IntegersOnlyWholeAndInRange) {
  EXPECT_EQ(parse_integer("12"), 12);
  EXPECT_EQ(parse_integer("-3"), -3);
  EXPECT_EQ(parse_integer("+4"), 4);
  for (const char* text : {"", "+", "-", " 1", "1 ", "0x10", "1,5", "1.0", "1e3", "+-1", "--1",
                           "12abc", "99999999999999999999"})
    EXPECT_FALSE(parse_integer(text).has_value()) << "'" << text << "'";
}

TEST(SpecText, ExactTextReadsBackAsTheSameNumber) {
  EXPECT_EQ(exact_text(0.1), "0.1");
  EXPECT_EQ(exact_text(10000000.53125), "10000000.53125");
  EXPECT_EQ(exact_text(1.0 / 3.0), "0.3333333333333333");
  EXPECT_EQ(exact_text(0.1f), "0.1");  // a float's own shortest text, not 0.100000001
  EXPECT_EQ(exact_text(-0.0), "-0");
  for (const double value : {1.0 / 3.0, 1e-300, -2.5e17, 4.9e-324})
    EXPECT_EQ(parse_decimal(exact_text(value)), value) << value;
}

// Whole, with UTF-8 kept but C0, DEL, C1 (encoded or raw), overlong forms and stray bytes escaped.
TEST(SpecText, PrintableTextEscapesControlsAndKeepsUtf8) {
  EXPECT_EQ(printable_text("rect:\x1B[2J-1"), "rect:\\x1B[2J-1");
  EXPECT_EQ(printable_text("caf\xC3\xA9 \xE2\x82\xAC\x7F"), "caf\xC3\xA9 \xE2\x82\xAC\\x7F");
  EXPECT_EQ(printable_text("\xC2\x9B\x9B\xC0\xAF\xE2\x82"), "\\xC2\\x9B\\x9B\\xC0\\xAF\\xE2\\x82");
  EXPECT_EQ(printable_text(std::string(200, 'z')), std::string(200, 'z'));
}

TEST(SpecText, QuotedTextIsShortAndPrintable) {
  EXPECT_EQ(quoted_text("abc"), "'abc'");
  EXPECT_EQ(quoted_text(std::string("a\0b\r\xC3", 5)), "'a\\x00b\\x0D\\xC3'");
  EXPECT_EQ(quoted_text(std::string(100, 'z'), 4), "'zzzz...'");
}

TEST(SpecText, SplitCommasKeepsEmptyItems) {
  EXPECT_EQ(split_commas(""), std::vector<std::string>{""});
  EXPECT_EQ(split_commas("1,,2,"), (std::vector<std::string>{"1", "", "2", ""}));
  EXPECT_EQ(split_commas("a"), std::vector<std::string>{"a"});
  EXPECT_EQ(split_at("1//3", '/'), (std::vector<std::string>{"1", "", "3"}));  // OBJ corners
}

}  // namespace
}  // namespace rvor
