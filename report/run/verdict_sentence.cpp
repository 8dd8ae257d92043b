// The verdict in plain words (see verdict_sentence.h).
#include "report/run/verdict_sentence.h"

#include "report/run/page_text.h"

namespace xsect {

using json = nlohmann::ordered_json;

std::string verdictSentence(const json& report) {
  const json& sampling = field(report, {"sampling"});
  const std::string verdict =
      field(sampling, {"verdict"}).is_string() ? field(sampling, {"verdict"}).get<std::string>() : "undetermined";
  const json& level = field(report, {"topology", "confidence", "level"});
  const std::string confidence = level.is_string() ? level.get<std::string>() : "";
  const json& cells = field(sampling, {"cells"});
  const auto count = [&](const char* k) {
    return field(cells, {k}).is_number() ? field(cells, {k}).get<long long>() : 0LL;
  };
  const long long total = count("total"), violated = count("violated"), undetermined = count("undetermined");
  const json& advised = field(sampling, {"advice", "slices"});
  const long long advice = advised.is_number() ? advised.get<long long>() : 0;
  const bool reachGiven = field(sampling, {"prior", "reach_interior_mm"}).is_number() ||
                          field(sampling, {"prior", "reach_exterior_mm"}).is_number();

  if (verdict == "satisfied")
    return "The slices are dense and transversal enough everywhere: by the thesis' theorems the result has the "
           "object's topology, provided the object's reach is at least the one given (sampling.reach_mm).";
  std::string s;
  // Which condition failed: the planes too far apart for the object's reach (density), or cutting its
  // surface at too grazing an angle (transversality).
  bool sparse = false, oblique = false;
  for (const auto& [name, state] : field(sampling, {"conditions"}).items()) {
    if (state != "violated") continue;
    sparse = sparse || name.find("density") != std::string::npos;
    oblique = oblique || name.find("transversality") != std::string::npos;
  }
  const std::string why = sparse && oblique ? "too far apart and cut the surface at too grazing an angle"
                          : sparse          ? "too far apart for the object's reach"
                          : oblique         ? "cut the surface at too grazing an angle"
                                            : "do not meet the thesis' sampling conditions";
  if (verdict == "violated")
    s = "The slices " + why + " in " + std::to_string(violated) + " of the " + std::to_string(total) +
        " cells between them, so the thesis' theorems do not prove the topology";
  else
    s = "The sampling conditions could not be decided in " + std::to_string(undetermined) + " of " +
        std::to_string(total) + " cells between the slices" +
        (reachGiven ? "" : " (the object's reach is not given: sampling.reach_mm)") +
        ", so the thesis' theorems do not prove the topology";
  if (confidence == "high")
    s += "; it is likely right all the same: no feature of the result is as thin as the data's own scale "
         "(confidence high).";
  else if (confidence == "medium")
    s += "; some features of the result are near the data's scale (confidence medium): check them in the view.";
  else if (confidence == "low")
    s += "; some features may be artefacts of the slicing (confidence low): if you know the object's topology, give "
         "it as reconstruction.topology.";
  else
    s += ".";
  if (advice > 0)
    s += " advice.yaml proposes " + std::to_string(advice) + " slice" + (advice == 1 ? "" : "s") +
         " that would bring the worst cells within the conditions.";
  return s;
}

}  // namespace xsect
