#pragma once
// Umbrella header of adamss::materials: constitutive laws W(E) -> S, dS/dE in the fibre frame.
// See law.hpp for the conventions (shear, Voigt order and scaling) every law follows.
#include "materials/elastic_constants.hpp"
#include "materials/factory.hpp"
#include "materials/guccione.hpp"
#include "materials/holzapfel_ogden.hpp"
#include "materials/hunter.hpp"
#include "materials/kinematics.hpp"
#include "materials/law.hpp"
#include "materials/neo_hookean.hpp"
#include "materials/svk.hpp"
#include "materials/voigt.hpp"
#include "materials/volumetric.hpp"
