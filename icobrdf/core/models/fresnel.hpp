#pragma once
// Fresnel reflectance of a smooth interface, unpolarized light, as used by the microfacet models.
// c = cos of the angle between the light direction and the facet normal, in [0, 1].
namespace icobrdf {

// Schlick's approximation F = f0 + (1 - f0) (1 - c)^5; f0 = reflectance at normal incidence, in [0, 1].
double fresnel_schlick(double c, double f0);

// Exact Fresnel reflectance of a dielectric (light arriving from the medium of index 1 onto a medium of
// relative index eta >= 1), average of s and p polarizations, in the form
//   g = sqrt(eta^2 - 1 + c^2),  F = 1/2 ((g - c)/(g + c))^2 (1 + ((c (g + c) - 1)/(c (g - c) + 1))^2).
// F(1) = ((eta - 1)/(eta + 1))^2, F(0) = 1 for eta > 1; eta = 1 (no interface) gives 0 everywhere.
// Total internal reflection (g^2 < 0, only possible for eta < 1) gives 1.
double fresnel_dielectric(double c, double eta);

}  // namespace icobrdf
