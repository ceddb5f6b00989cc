"""lensray's glass as a Mitsuba 3 BSDF (`gltf_dielectric`), to tell model from implementation.

It evaluates what lensray's reference evaluates for a clear dielectric with transmission 1
(crates/lensray-core/src/reference/brdf.rs and transmission.rs): Schlick's Fresnel with f0 from
the index (from inside a volume on the refracted cosine, 1 beyond the critical angle), GGX with
the height-correlated Smith visibility, Walter et al.'s BTDF without its Fresnel times (1 - F),
roughness clamped to 0.045 (alpha >= 0.002025). It draws directions its own way, as Mitsuba's
`roughdielectric` does: a visible normal first, then reflection or refraction about it with
probability F(v.h), which reaches every direction the model sends light to. So Mitsuba with this
BSDF renders lensray's model without lensray's sampling: against lensray it checks lensray's
estimator, against Mitsuba's own `roughdielectric` it measures the model difference.

Import it after `mi.set_variant` (a JIT variant: Python traces it once per kernel), then
`register()`; the dictionary is {"type": "gltf_dielectric", "ior": 1.5, "roughness": r}.
"""

import drjit as dr
import mitsuba as mi

if __name__ == "__main__":
    # The class derives from the variant's BSDF: a variant first.
    mi.set_variant("llvm_ad_rgb")

MIN_ROUGHNESS = 0.045


class GltfDielectric(mi.BSDF):
    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.ior = float(props.get("ior", 1.5))
        roughness = max(float(props.get("roughness", 0.0)), MIN_ROUGHNESS)
        self.alpha = min(roughness, 1.0) ** 2
        self.f0 = ((self.ior - 1) / (self.ior + 1)) ** 2
        # "exact": the unpolarized Fresnel equations instead of Schlick's, to tell the Fresnel's
        # share of a difference from the rest of the model's.
        self.exact = props.get("fresnel", "schlick") == "exact"
        self.distribution = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.alpha, True)
        sides = mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        reflection = mi.BSDFFlags.GlossyReflection | sides
        transmission = mi.BSDFFlags.GlossyTransmission | sides | mi.BSDFFlags.NonSymmetric
        self.m_components = [reflection, transmission]
        self.m_flags = reflection | transmission

    # lensray's shading works above the normal, on the viewer's side: the frame is turned so
    # that v.z > 0, and the relative index is the index (entering) or its inverse (leaving).
    def _frame(self, si, wo):
        s = dr.select(mi.Frame3f.cos_theta(si.wi) >= 0, 1.0, -1.0)
        v = mi.Vector3f(si.wi.x, si.wi.y, si.wi.z * s)
        l = mi.Vector3f(wo.x, wo.y, wo.z * s)
        eta = dr.select(s > 0, self.ior, 1.0 / self.ior)
        return v, l, eta

    def _fresnel(self, cos, eta):
        """Schlick's, on the outside cosine; 1 beyond the critical angle (brdf.rs)."""
        sin2 = (1 - cos * cos) / (eta * eta)
        if self.exact:
            cos_t = dr.safe_sqrt(1 - sin2)
            rs = (cos - eta * cos_t) / (cos + eta * cos_t)
            rp = (eta * cos - cos_t) / (eta * cos + cos_t)
            return dr.select(sin2 >= 1, 1.0, 0.5 * (rs * rs + rp * rp))
        outside = dr.select(eta >= 1, cos, dr.safe_sqrt(1 - sin2))
        m = dr.clip(1 - outside, 0.0, 1.0)
        schlick = self.f0 + (1 - self.f0) * m * m * m * m * m
        return dr.select((eta < 1) & (sin2 >= 1), 1.0, schlick)

    def _d(self, n_dot_h):
        a2 = self.alpha * self.alpha
        c2 = n_dot_h * n_dot_h
        d = (1 - c2) + c2 * a2
        return dr.select(n_dot_h > 0, a2 / (dr.pi * d * d), 0.0)

    def _visibility(self, n_dot_l, n_dot_v):
        a2 = self.alpha * self.alpha
        gv = n_dot_l * dr.sqrt(n_dot_v * n_dot_v * (1 - a2) + a2)
        gl = n_dot_v * dr.sqrt(n_dot_l * n_dot_l * (1 - a2) + a2)
        return 0.5 / (gv + gl)

    def _visible_pdf(self, n_dot_v, n_dot_h):
        """D_v(h) / (4 v.h) = G1(v) D(h) / (4 n.v)."""
        a2 = self.alpha * self.alpha
        lam = dr.sqrt(a2 + (1 - a2) * n_dot_v * n_dot_v)
        return self._d(n_dot_h) / (2 * (n_dot_v + lam))

    def _refraction_normal(self, v, l, eta):
        h = -dr.normalize(v + eta * l)
        h = dr.select(h.z < 0, -h, h)
        return h, dr.dot(v, h), dr.dot(l, h)

    def _eval_pdf(self, v, l, eta):
        """f |cos| and the density of this BSDF's draws, in the turned frame."""
        up = l.z > 0
        # Reflection.
        hr = dr.normalize(l + v)
        vhr = dr.abs(dr.dot(v, hr))
        fr = self._fresnel(vhr, eta)
        value_r = fr * self._d(hr.z) * self._visibility(l.z, v.z) * l.z
        pdf_r = fr * self._visible_pdf(v.z, hr.z)
        # Transmission (transmission.rs: f_t = 4 |l.h| |v.h| D V / (v.h + eta l.h)^2).
        ht, vh, lh = self._refraction_normal(v, l, eta)
        ok = (vh > 0) & (lh < 0)
        den = vh + eta * lh
        nl = -l.z
        lobe = 4 * vh * (-lh) * self._d(ht.z) * self._visibility(nl, v.z) / (den * den)
        ft = 1 - self._fresnel(dr.clip(vh, 0.0, 1.0), eta)
        value_t = dr.select(ok, ft * lobe * nl, 0.0)
        normal_pdf = 4 * vh * self._visible_pdf(v.z, ht.z)
        pdf_t = dr.select(ok, ft * normal_pdf * eta * eta * (-lh) / (den * den), 0.0)
        valid = (v.z > 0) & (l.z != 0)
        value = dr.select(valid, dr.select(up, value_r, value_t), 0.0)
        pdf = dr.select(valid, dr.select(up, pdf_r, pdf_t), 0.0)
        return value, pdf

    def eval(self, ctx, si, wo, active=True):
        v, l, eta = self._frame(si, wo)
        value, _ = self._eval_pdf(v, l, eta)
        return mi.Color3f(dr.select(active, value, 0.0))

    def pdf(self, ctx, si, wo, active=True):
        v, l, eta = self._frame(si, wo)
        _, pdf = self._eval_pdf(v, l, eta)
        return dr.select(active, pdf, 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        v, l, eta = self._frame(si, wo)
        value, pdf = self._eval_pdf(v, l, eta)
        return mi.Color3f(dr.select(active, value, 0.0)), dr.select(active, pdf, 0.0)

    def sample(self, ctx, si, sample1, sample2, active=True):
        s = dr.select(mi.Frame3f.cos_theta(si.wi) >= 0, 1.0, -1.0)
        v, _, eta = self._frame(si, si.wi)
        h, _ = self.distribution.sample(v, sample2)
        vh = dr.dot(v, h)
        f = self._fresnel(vh, eta)
        reflect = sample1 < f
        l_r = 2 * vh * h - v
        sin2 = (1 - vh * vh) / (eta * eta)
        l_t = -v / eta + h * (vh / eta - dr.safe_sqrt(1 - sin2))
        l = dr.select(reflect, l_r, l_t)
        value, pdf = self._eval_pdf(v, l, eta)
        ok = active & dr.select(reflect, l.z > 0, l.z < 0) & (pdf > 0)
        bs = dr.zeros(mi.BSDFSample3f)
        bs.wo = mi.Vector3f(l.x, l.y, l.z * s)
        bs.pdf = dr.select(ok, pdf, 0.0)
        bs.eta = dr.select(reflect, 1.0, eta)
        bs.sampled_component = dr.select(reflect, mi.UInt32(0), mi.UInt32(1))
        bs.sampled_type = dr.select(reflect, mi.UInt32(+mi.BSDFFlags.GlossyReflection),
                                    mi.UInt32(+mi.BSDFFlags.GlossyTransmission))
        return bs, mi.Color3f(dr.select(ok, value / pdf, 0.0))

    def traverse(self, callback):
        pass

    def to_string(self):
        return f"GltfDielectric[ior={self.ior}, alpha={self.alpha}]"


def register():
    mi.register_bsdf("gltf_dielectric", lambda props: GltfDielectric(props))


def leaving_table(roughness=0.3, ior=1.5, draws=1 << 20):
    """What lensray's model reflects (R) and lets out (eta^2 T, eta = 1 / ior) of light seen from
    inside a volume at n.v = mu: the mean weights of this BSDF's reflected and transmitted draws
    (Monte Carlo, `draws` a row). Below the critical cosine sqrt(1 - 1 / ior^2) a smooth surface
    reflects all; a rough one still lets out what its microfacets turned below it."""
    import numpy as np
    bsdf = mi.load_dict({"type": "gltf_dielectric", "ior": ior, "roughness": roughness})
    rng = np.random.default_rng(1)
    rows = []
    for mu in (0.9, 0.8, 0.76, 0.745, 0.73, 0.7, 0.6, 0.5):
        si = dr.zeros(mi.SurfaceInteraction3f, draws)
        si.wi = mi.Vector3f(float((1 - mu * mu) ** 0.5), 0.0, -float(mu))
        si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
        u = [mi.Float(rng.random(draws).astype(np.float32)) for _ in range(3)]
        bs, weight = bsdf.sample(mi.BSDFContext(), si, u[0], mi.Point2f(u[1], u[2]))
        w = np.array(weight.x)
        through = np.array(bs.sampled_component) == 1
        r, t = w[~through].sum() / draws, w[through].sum() / draws
        rows.append((mu, r, t / ior ** 2))
    return rows


def beyond_critical(roughness=0.3, ior=1.5, draws=1 << 20):
    """Of the light refracted into a ball at each angle of incidence (degrees), the share that
    meets the far side beyond the critical angle: in a sphere the far side sees a chord at the
    angle it makes with the entry's normal."""
    import numpy as np
    bsdf = mi.load_dict({"type": "gltf_dielectric", "ior": ior, "roughness": roughness})
    critical = (1 - 1 / ior ** 2) ** 0.5
    rng = np.random.default_rng(2)
    rows = []
    for degrees in (45, 60, 70, 75, 80, 85):
        angle = np.radians(degrees)
        si = dr.zeros(mi.SurfaceInteraction3f, draws)
        si.wi = mi.Vector3f(float(np.sin(angle)), 0.0, float(np.cos(angle)))
        si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
        u = [mi.Float(rng.random(draws).astype(np.float32)) for _ in range(3)]
        bs, weight = bsdf.sample(mi.BSDFContext(), si, u[0], mi.Point2f(u[1], u[2]))
        w = np.array(weight.x) * (np.array(bs.sampled_component) == 1)
        beyond = -np.array(bs.wo.z) < critical
        rows.append((degrees, (w * beyond).sum() / w.sum()))
    return rows


if __name__ == "__main__":
    # python gltf_dielectric.py: the tables docs/mitsuba-glass.md quotes.
    register()
    print("leaving glass of index 1.5, roughness 0.3: n.v, R, eta^2 T, R + eta^2 T")
    for mu, r, t in leaving_table():
        print(f"  {mu:5.3f}  {r:.4f}  {t:.4f}  {r + t:.4f}")
    print("entering a ball of index 1.5, roughness 0.3: angle, share of the refracted light that"
          " meets the far side beyond the critical angle")
    for degrees, share in beyond_critical():
        print(f"  {degrees:2d}  {share:.3f}")
