// STUB: replaced by the evaluation implementation.
#include <stdexcept>
#include "pipeline/commands.h"
namespace xsect {
int evalCommand(const EvalOptions&) { throw std::runtime_error("eval: not implemented"); }
}  // namespace xsect
