// STUB: replaced by the phantom implementation.
#include <stdexcept>
#include "pipeline/commands.h"
namespace xsect {
int phantomCommand(const PhantomOptions&) { throw std::runtime_error("phantom: not implemented"); }
}  // namespace xsect
