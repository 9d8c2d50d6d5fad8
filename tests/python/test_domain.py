"""libsinter on one subdomain of a host's decomposition through the Python package
(sinter.domain, issue 43): a host of one subdomain written in Python gives the same bits as
the run without domain operations (nothing is summed in another order), and ghosts are
checked and counted."""

import unittest

import sinter
from sinter import domain


class OneSubdomain(domain.DomainHost):
    """The collective operations of a decomposition into one subdomain: reductions of one
    part, no other subdomain to take ghosts from."""

    def __init__(self):
        self.calls = {"reduce": 0, "exscan": 0, "halo": 0, "redistribute": 0}

    def reduce(self, values, type, op):
        self.calls["reduce"] += 1
        return values

    def exscan(self, value):
        self.calls["exscan"] += 1
        return 0, value

    def halo(self, direction, width, rows, ids, owned, ghosts):
        self.calls["halo"] += 1
        assert width == domain.HALO_STATE_WIDTH and ghosts == 0

    def redistribute(self, stepper):
        self.calls["redistribute"] += 1
        self.cutoff = domain.ghost_cutoff(stepper)
        domain.set_ghosts(self.particles, [], [], [], [], [], [], [], [], [], [])


def bed(ctx, host=None):
    material = sinter.Material(ctx, "glass", youngs_modulus=1e7, poisson_ratio=0.3,
                               density=2500.0, damping_ratio=0.3, friction_static=0.5,
                               friction_dynamic=0.5)
    ps = sinter.Particles(ctx)
    ps.set_material(0, material)
    walls = sinter.Walls(ctx)
    walls.add_plane((0, 0, 0), (0, 0, 1), material)
    points = [(1e-3 + 1.97e-3 * (k % 4), 1e-3 + 1.97e-3 * (k // 4 % 4),
               0.99e-3 + 1.97e-3 * (k // 16)) for k in range(48)]
    ps.add(points, 1e-3, ids=[1000 + (7 * k) % 48 for k in range(48)])
    stepper = sinter.Stepper(ctx, ps, walls, dt=2e-6,
                             forces=[sinter.ForceModel(ctx, "gravity"),
                                     sinter.ForceModel(ctx, "hertz_mindlin")])
    if host is not None:
        host.particles = ps
        domain.set_domain_ops(stepper, host)
    stepper.step(40)
    with ps.view("position") as x:
        positions = [float(x[i, d]) for i in range(48) for d in range(3)]
    return ps, walls, stepper, positions


class DomainTest(unittest.TestCase):
    def test_one_subdomain_same_bits(self):
        with sinter.Context() as ctx:
            _, walls, _, plain = bed(ctx)
            plain_force = walls.force(0)
        with sinter.Context() as ctx:
            host = OneSubdomain()
            _, walls, stepper, hosted = bed(ctx, host)
            self.assertEqual(hosted, plain)
            self.assertEqual(walls.force(0), plain_force)
            self.assertEqual(domain.wall_force_local(walls, 0), plain_force)
            self.assertGreater(host.calls["redistribute"], 0)
            self.assertGreaterEqual(host.calls["halo"], 80)  # two forward halos a step
            self.assertGreater(host.cutoff, 2e-3)  # 2 r_max + skin
            stats = domain.stats_global(stepper)
            self.assertEqual(stats.steps, 40)
            domain.set_domain_ops(stepper, None)

    def test_ghosts_checked(self):
        with sinter.Context() as ctx:
            ps, _, _, _ = bed(ctx)
            one = [(0.0, 0.0, 0.0)]
            with self.assertRaises(sinter.InvalidArgument):  # the id of an owned particle
                domain.set_ghosts(ps, [1000], [(0, 0, 5e-3)], one, one, one, [1e-3], [1e-5],
                                  [4e-12], [300.0], [0])
            domain.set_ghosts(ps, [7], [(0, 0, 5e-3)], one, one, one, [1e-3], [1e-5], [4e-12],
                              [300.0], [0], owners=[1])
            self.assertEqual(ps.count, 49)

    def test_enums(self):
        self.assertEqual(int(domain.ReduceOp.MAX), 2)
        self.assertEqual(int(domain.ReduceType.U64), 2)
        self.assertEqual(int(domain.HaloDir.REVERSE), 1)


if __name__ == "__main__":
    unittest.main()
