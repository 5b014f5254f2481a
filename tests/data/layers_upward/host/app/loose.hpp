// A file of app/ outside its layers, for test layer_order_catches_file_outside_layers.
#pragma once
