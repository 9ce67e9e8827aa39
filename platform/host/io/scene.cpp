#include "scene.hpp"
