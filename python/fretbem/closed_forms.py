"""Closed forms fretbem is checked against and users compare with (SI units): effective moduli
(README, "Conventions and physics"), Hertz, Cattaneo–Mindlin and Mindlin–Deresiewicz for a
sphere under a constant normal force (Johnson, Contact Mechanics, §§4.2, 7.2, 7.5). Pure
numpy: the plot tools load this file without the compiled module.
"""
import numpy as np


def _positive(name, value):
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"Contact: {name} = {value} must be a positive finite number")


class Contact:
    """A sphere of radius R pressed with force P on a half-space; bodies as (E, nu) pairs, the
    second None for a rigid indenter."""

    def __init__(self, body1, body2=None, mu=0.3, radius=None, normal_force=None):
        # Unchecked, a negative radius gives complex energies and 0 a ZeroDivisionError.
        _positive("mu", mu)
        if radius is not None:
            _positive("radius", radius)
        if normal_force is not None:
            _positive("normal_force", normal_force)
        inv_e, inv_g = 0.0, 0.0
        for body in (body1, body2):
            if body is None:
                continue
            E, nu = body
            _positive("E", E)
            if not -1 < nu <= 0.5:
                raise ValueError(f"Contact: nu = {nu} is not a Poisson ratio in (-1, 0.5]")
            inv_e += (1 - nu**2) / E
            inv_g += (2 - nu) / (4 * E / (2 * (1 + nu)))
        self.E_star, self.G_star = 1 / inv_e, 1 / inv_g
        self.mu, self.R, self.P = mu, radius, normal_force
        self.sphere = radius is not None

    @property
    def hertz_ok(self):
        return self.sphere and self.R is not None and self.P is not None

    # Values as properties; the hertz_* methods return the same numbers (kept for scripts).
    @property
    def contact_radius(self):
        """Hertz contact radius a = (3 P R / 4 E*)^(1/3) (m)."""
        return self.hertz_radius()

    @property
    def indentation(self):
        """Hertz indentation delta = a^2 / R (m)."""
        return self.hertz_indentation()

    @property
    def peak_pressure(self):
        """Hertz peak pressure p0 = 3 P / (2 pi a^2) (Pa)."""
        return self.hertz_peak_pressure()

    def hertz_radius(self):
        """a = (3 P R / 4 E*)^(1/3)."""
        self._need_sphere("hertz_radius")
        return (3 * self.P * self.R / (4 * self.E_star)) ** (1 / 3)

    def hertz_indentation(self):
        """delta = a^2 / R."""
        return self.hertz_radius() ** 2 / self.R

    def hertz_peak_pressure(self):
        """p0 = 3 P / (2 pi a^2)."""
        return 3 * self.P / (2 * np.pi * self.hertz_radius() ** 2)

    def _need_sphere(self, what):
        if not self.hertz_ok:
            raise ValueError(f"Contact.{what}: needs radius and normal_force")

    def sliding_shift(self, delta):
        """Full-sliding shift U* = mu delta E*/G* (delta: normal approach)."""
        return self.mu * delta * self.E_star / self.G_star

    def _below_sliding(self, Q):
        if np.any(~(np.abs(np.asarray(Q, dtype=float)) <= self.mu * self.P)):
            raise ValueError(f"Contact: tangential force {Q} N is not within mu P = "
                             f"{self.mu * self.P} N (full sliding)")

    def stick_radius(self, Q):
        """Cattaneo: c = a (1 - Q/mu P)^(1/3)."""
        self._below_sliding(Q)
        return self.hertz_radius() * (1 - abs(Q) / (self.mu * self.P)) ** (1 / 3)

    def md_shift(self, Q):
        """Monotone Cattaneo–Mindlin shift under tangential force Q (|Q| < mu P):
        (3 mu P / 4 a G*) (1 - (1 - Q/mu P)^(2/3)), odd in Q."""
        self._below_sliding(Q)
        a, muP = self.hertz_radius(), self.mu * self.P
        Q = np.asarray(Q, dtype=float)
        return np.sign(Q) * 3 * muP / (4 * a * self.G_star) * (1 - (1 - np.abs(Q) / muP) ** (2 / 3))

    def md_loop(self, Q_star, points=200):
        """Steady Mindlin–Deresiewicz loop between -Q* and +Q* (Masing: branches are the
        monotone curve doubled in size): (U, F) along unloading then reloading."""
        Q = np.linspace(Q_star, -Q_star, points)
        down = self.md_shift(Q_star) - 2 * self.md_shift((Q_star - Q) / 2)
        # Reloading is unloading mirrored through the origin: U_up(-F) = -U_down(F).
        return np.concatenate((down, -down)), np.concatenate((Q, -Q))

    def tangential_force(self, U):
        """Monotone Cattaneo–Mindlin force under a tangential shift U (odd in U):
        mu P (1 - (1 - |U|/u*)^(3/2)) up to the full-sliding shift u* (Hertz indentation), then
        mu P (gross slip)."""
        muP, us = self.mu * self.P, self.sliding_shift(self.hertz_indentation())
        U = np.asarray(U, dtype=float)
        return np.sign(U) * muP * (1 - (1 - np.minimum(np.abs(U) / us, 1)) ** 1.5)

    def displacement_loop(self, D, points=200):
        """Steady loop under displacement control between -D and +D (Masing: each branch is the
        monotone curve doubled in size), partial or gross slip: (U, F) along unloading then
        reloading. Its area is displacement_energy(D)."""
        U = np.linspace(D, -D, points)
        down = self.tangential_force(D) - 2 * self.tangential_force((D - U) / 2)
        return np.concatenate((U, -U)), np.concatenate((down, -down))

    def displacement_energy(self, D):
        """Energy per cycle (J) under displacement control between -D and +D: Mindlin–Deresiewicz
        at the force amplitude q = 1 - (1 - D/u*)^(3/2) below full sliding, and beyond it the
        gross-slip line 4 mu P (D - 4u*/5) (the rectangle 2D x 2 mu P less two corners of area
        (8/5) mu P u*, where the reversed branches take 2u* to reach -+mu P), u* = U* above."""
        muP, us = self.mu * self.P, self.sliding_shift(self.hertz_indentation())
        D = np.asarray(D, dtype=float)
        q = 1 - (1 - np.minimum(D / us, 1)) ** 1.5
        return np.where(D < us, self.md_energy(q * muP), 4 * muP * (D - 0.8 * us))

    def md_energy(self, Q_star):
        """Energy per cycle (J): (9 mu^2 P^2 / 10 a)(4/G*)[1 - (1-x)^(5/3) - (5x/6)(1 + (1-x)^(2/3))],
        x = Q*/mu P (Johnson eq. 7.60 with (2-nu1)/G1 + (2-nu2)/G2 = 4/G*)."""
        self._below_sliding(Q_star)
        a, muP = self.hertz_radius(), self.mu * self.P
        x = Q_star / muP
        bracket = 1 - (1 - x) ** (5 / 3) - 5 * x / 6 * (1 + (1 - x) ** (2 / 3))
        return 9 * muP**2 / (10 * a) * 4 / self.G_star * bracket
