#include "app/monitors/bq4050_app.hpp"

namespace fw::app {

// The image's monitor task: its code (the loop with the gauge's part folded in) is compiled here once.
template class MonitorTask<Bq4050Device>;

}  // namespace fw::app
