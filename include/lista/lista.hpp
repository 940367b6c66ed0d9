// Everything a plugin author needs.
#pragma once

#include <lista/context.hpp>
#include <lista/data.hpp>
#include <lista/error.hpp>
#include <lista/param_table.hpp>
#include <lista/params.hpp>
#include <lista/plugin.hpp>
#include <lista/stage.hpp>
#include <lista/version.hpp>
