// STUB: replaced by the pipeline implementation.
#include <stdexcept>
#include "pipeline/commands.h"
namespace xsect {
int runCommand(const RunOptions&) { throw std::runtime_error("run: not implemented"); }
int checkCommand(const RunOptions&) { throw std::runtime_error("check: not implemented"); }
}  // namespace xsect
