"""controlext: state observers for noisy measurements, on python-control.

Every observer is a :class:`control.StateSpace` whose realisation is its
estimation-error system, so python-control's tools apply directly.
"""

# errors
from .exceptions import (ControlextError, DimensionError, ArgumentError,
                         ParameterError, NotDetectableError, RegionError,
                         SolverError, VerificationError, GainWarning)
# the H∞ norm with MATLAB's meaning  (norms.py)
from .norms import hinfnorm, is_stable
# the engine: generalised plant, options, pole regions, reports
# (synthesis/)
from .synthesis import (ObserverProblem, SynthesisOptions, RefineOptions,
                        DesignReport, Region, HalfPlane, Disk, Sector)
# the observer base  (observers.py)
from .observers import Observer
# the Luenberger observer  (luenberger.py)
from .luenberger import (LuenbergerObserver, luenberger_observer,
                         hinf_observer)
# coupled Luenberger observers  (coupled.py)
from .coupled import CoupledObserver, coupled_observer
# GI observers  (gi.py)
from .gi import GIObserver, gi_observer, range_basis, projection
# analysis of Section III  (analysis.py)
from .analysis import (spectral_abscissa, log_norm, eig_condition,
                       ISSEstimate, iss_estimate, ConditionCheck,
                       check_lemma_3_2, check_lemma_3_3, check_theorem_3_5,
                       steady_state_error, crossing_time, tradeoff_curve)
# simulation and design maps  (simulate.py, maps.py)
from .simulate import simulate
from .maps import DesignMap, design_map
# trade-offs side by side, with the Kalman filter  (compare.py)
from .compare import Comparison, compare, kalman_observer
from .synthesis.tradeoff import Tradeoff
from .sweep import Sweep, sweep
# several plant models: building them, checking a design between them
# (models.py)
from .models import model_set, ModelCheck, check_models
# plots (matplotlib, optional)  (plot.py)
from .plot import (error_plot, estimate_plot, tradeoff_plot,
                   design_map_plot, pole_region_plot, sweep_plot)

__version__ = '0.2.0'

__all__ = [
    'ControlextError', 'DimensionError', 'ArgumentError', 'ParameterError',
    'NotDetectableError', 'RegionError', 'SolverError', 'VerificationError',
    'GainWarning',
    'Region', 'HalfPlane', 'Disk', 'Sector',
    'hinfnorm', 'is_stable',
    'ObserverProblem', 'SynthesisOptions', 'RefineOptions', 'DesignReport',
    'Observer', 'LuenbergerObserver', 'CoupledObserver',
    'luenberger_observer', 'hinf_observer', 'coupled_observer',
    'GIObserver', 'gi_observer', 'range_basis', 'projection',
    'spectral_abscissa', 'log_norm', 'eig_condition', 'ISSEstimate',
    'iss_estimate', 'ConditionCheck', 'check_lemma_3_2', 'check_lemma_3_3',
    'check_theorem_3_5', 'steady_state_error', 'crossing_time',
    'tradeoff_curve', 'simulate', 'DesignMap', 'design_map',
    'error_plot', 'estimate_plot', 'tradeoff_plot', 'design_map_plot',
    'pole_region_plot', 'Comparison', 'compare', 'kalman_observer',
    'Tradeoff', 'Sweep', 'sweep', 'sweep_plot',
    'model_set', 'ModelCheck', 'check_models',
]
