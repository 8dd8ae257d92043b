// Library versions from their version headers (see library_versions.h).
#include "pipeline/library_versions.h"

#include <CGAL/version.h>
#include <Eigen/Core>
#include <oneapi/tbb/version.h>
#include <openvdb/version.h>
#include <opencv2/core/version.hpp>

namespace xsect {

std::map<std::string, std::string> libraryVersions() {
  return {{"xsect", XSECT_VERSION},
          {"opencv", CV_VERSION},
          {"openvdb", OPENVDB_LIBRARY_VERSION_STRING},
          {"cgal", CGAL_VERSION_STR},
          {"tbb", TBB_VERSION_STRING},
          {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) +
                        "." + std::to_string(EIGEN_MINOR_VERSION)}};
}

}  // namespace xsect
