// SPDX-License-Identifier: MIT
#include "core/io/gismo_xml_writer.h"

#include "core/io/number_text.h"

namespace volspline::io {

std::string serialize_gismo_xml(const spline::BsplineMultipatch& multipatch) {
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<xml>\n";
  const int num_patches = int(multipatch.patches.size());
  for (int p = 0; p < num_patches; ++p) {
    const spline::BsplineVolume& volume = multipatch.patches[p];
    out += " <Geometry type=\"TensorBSpline3\" id=\"";
    append_number(out, (long long)p);
    out += "\">\n  <Basis type=\"TensorBSplineBasis3\">\n";
    for (int a = 0; a < 3; ++a) {
      out += "   <Basis type=\"BSplineBasis\" index=\"";
      append_number(out, (long long)a);
      out += "\">\n    <KnotVector degree=\"3\">";
      for (std::size_t k = 0; k < volume.knots(a).size(); ++k) {
        if (k) out += ' ';
        append_number(out, volume.knots(a)[k]);
      }
      out += "</KnotVector>\n   </Basis>\n";
    }
    out += "  </Basis>\n  <coefs geoDim=\"";
    append_number(out, (long long)volume.dimension());
    out += "\">\n";
    const Eigen::MatrixXd& P = volume.control_points();
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
      for (Eigen::Index d = 0; d < P.cols(); ++d) {
        if (d) out += ' ';
        append_number(out, P(i, d));
      }
      out += '\n';
    }
    out += "</coefs>\n </Geometry>\n";
  }
  out += " <MultiPatch parDim=\"3\" id=\"";
  append_number(out, (long long)num_patches);
  out += "\">\n  <patches type=\"id_range\">0 ";
  append_number(out, (long long)(num_patches - 1));
  out += "</patches>\n  <interfaces>\n";
  for (const spline::MultipatchInterface& in : multipatch.interfaces) {
    for (const long long v : {(long long)in.patch[0], (long long)in.side[0] + 1, (long long)in.patch[1],
                              (long long)in.side[1] + 1, (long long)in.axis[0], (long long)in.axis[1],
                              (long long)in.axis[2], (long long)(in.sign[0] > 0), (long long)(in.sign[1] > 0),
                              (long long)(in.sign[2] > 0)}) {
      append_number(out, v);
      out += ' ';
    }
    out.back() = '\n';
  }
  out += "</interfaces>\n  <boundary>\n";
  for (const spline::MultipatchBoundary& b : multipatch.boundary) {
    append_number(out, (long long)b.patch);
    out += ' ';
    append_number(out, (long long)b.side + 1);
    out += '\n';
  }
  out += "</boundary>\n </MultiPatch>\n</xml>\n";
  return out;
}

}  // namespace volspline::io
