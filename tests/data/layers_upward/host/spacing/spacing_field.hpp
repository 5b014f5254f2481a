// The included file of tests/data/layers_upward (the check reads includes; nothing is compiled).
#pragma once
