#pragma once
// JSON form of a look (every value, with units in the key names), for `--json` reports.
#include <nlohmann/json_fwd.hpp>

#include "foldcast/looks/looks.hpp"

namespace foldcast::looks {

// Found by nlohmann::json through ADL: `nlohmann::json j = look;`.
void to_json(nlohmann::json& json, const Look& look);

}  // namespace foldcast::looks
