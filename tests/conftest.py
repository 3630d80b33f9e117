import numpy as np
import pytest

import pinograsp as pg
from pinograsp import analytic

A, L, MU, TAU = 0.05, 0.1, 0.5, 1.0


@pytest.fixture(scope="session")
def pinch():
    return analytic.pinch(a=A, L=L, mu=MU)


def rot_z(phi: float) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def transform_model(model_contacts, Rm=np.eye(3), t=np.zeros(3), length=1.0, stiffness=1.0, **kw):
    """Rebuild contacts after a rigid motion (Rm, t) and a change of length unit / stiffness."""
    out = []
    for c in model_contacts:
        jac = None if c.jacobian is None else length * (Rm @ c.jacobian)
        out.append(
            pg.Contact(
                point=length * (Rm @ c.point + t),
                normal=Rm @ c.normal,
                mu=c.mu,
                jacobian=jac,
                tangent=Rm @ c.tangent,
                stiffness=stiffness * c.stiffness,
                name=c.name,
            )
        )
    return out
