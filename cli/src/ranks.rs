//! `mpirun -np N perifrac run SCENE` (issue 35, docs/ranks.md): MPI behind the
//! simulator's [`Ranks`] when the binary is built with the `mpi` feature (rsmpi over
//! the system's OpenMPI). MPI starts only when the process was launched by an MPI
//! launcher with more than one rank; a plain `perifrac run` never touches it. A
//! binary built without the feature refuses to run as one of several ranks, instead
//! of running the scene N times into one cache.

use std::sync::Arc;

use perifrac_sim::ranks::Ranks;

use crate::commands::Failure;

/// The ranks a launcher says it started, from the variables OpenMPI
/// (`OMPI_COMM_WORLD_SIZE`) and PMI launchers (MPICH's Hydra, Slurm's `srun`:
/// `PMI_SIZE`) set; `None` when not started by one.
fn launched_ranks() -> Option<usize> {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"]
        .iter()
        .find_map(|name| std::env::var(name).ok()?.trim().parse().ok())
}

/// The ranks of this run: `ranks` is `None` in one process.
pub struct Launch {
    /// The ranks, when more than one runs.
    pub ranks: Option<Arc<dyn Ranks>>,
    /// MPI, finalized when the launch is dropped.
    #[cfg(feature = "mpi")]
    _universe: Option<mpi::environment::Universe>,
}

impl Launch {
    /// One process, without MPI.
    pub fn single() -> Launch {
        Launch {
            ranks: None,
            #[cfg(feature = "mpi")]
            _universe: None,
        }
    }

    /// Whether this process writes the cache and prints: rank 0, or the only process.
    pub fn leads(&self) -> bool {
        self.ranks.as_ref().is_none_or(|r| r.rank() == 0)
    }

    /// Ends a distributed run that failed on this rank: prints the error (with this
    /// rank's number) and aborts every rank with its exit code, since the others may
    /// be waiting in a collective this rank will not reach. Returns the failure as
    /// it is in one process.
    pub fn fail(&self, failure: Failure) -> Failure {
        let Some(ranks) = &self.ranks else {
            return failure;
        };
        eprintln!("error (rank {}): {:#}", ranks.rank(), failure.error);
        abort(failure.code)
    }
}

/// Starts MPI when launched as one of several ranks.
#[cfg(feature = "mpi")]
pub fn launch() -> Result<Launch, Failure> {
    use mpi::environment::Threading;
    use mpi::traits::Communicator;
    if launched_ranks().is_none_or(|n| n <= 1) {
        return Ok(Launch::single());
    }
    // The simulator calls MPI from one thread at a time (the step's main thread,
    // between its parallel passes).
    let Some((universe, _)) = mpi::initialize_with_threading(Threading::Serialized) else {
        return Err(Failure::input(anyhow::anyhow!(
            "MPI was initialized before perifrac started it"
        )));
    };
    let world = universe.world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    Ok(Launch {
        ranks: (size > 1).then(|| Arc::new(Mpi { rank, size }) as Arc<dyn Ranks>),
        _universe: Some(universe),
    })
}

/// Refuses to run as one of several ranks without MPI.
#[cfg(not(feature = "mpi"))]
pub fn launch() -> Result<Launch, Failure> {
    without_mpi(launched_ranks())
}

/// The launch of a build without MPI started as one of `launched` ranks: one
/// process, or a refusal (exit 2) that says how to build it. Compiled for the tests
/// of the `mpi` build too, where CI runs them.
#[cfg(any(test, not(feature = "mpi")))]
fn without_mpi(launched: Option<usize>) -> Result<Launch, Failure> {
    match launched {
        Some(n) if n > 1 => Err(Failure::input(anyhow::anyhow!(
            "started as one of {n} MPI ranks, but this perifrac was built without MPI: \
             every rank would run the whole scene into the same cache. Build it with \
             `cargo build --release --features mpi` (needs OpenMPI: apt install \
             libopenmpi-dev openmpi-bin libclang-dev), or run it without mpirun"
        ))),
        _ => Ok(Launch::single()),
    }
}

#[cfg(feature = "mpi")]
fn abort(code: u8) -> ! {
    use mpi::traits::Communicator;
    mpi::topology::SimpleCommunicator::world().abort(i32::from(code))
}

#[cfg(not(feature = "mpi"))]
fn abort(code: u8) -> ! {
    std::process::exit(i32::from(code))
}

/// MPI_COMM_WORLD. The communicator is named at each call rather than kept, so
/// that this stays `Send + Sync` as the models that hold it must be.
#[cfg(feature = "mpi")]
#[derive(Debug)]
struct Mpi {
    rank: usize,
    size: usize,
}

#[cfg(feature = "mpi")]
impl Ranks for Mpi {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    /// The counts first (MPI_Allgather), then the values (MPI_Allgatherv).
    fn gather(&self, mine: &[f64]) -> Vec<Vec<f64>> {
        use mpi::datatype::PartitionMut;
        use mpi::traits::CommunicatorCollectives;
        let world = mpi::topology::SimpleCommunicator::world();
        let mut counts = vec![0i32; self.size];
        let count = i32::try_from(mine.len()).unwrap_or_else(|_| {
            eprintln!(
                "error: rank {} sends {} values in one step, past MPI's count",
                self.rank,
                mine.len()
            );
            abort(1)
        });
        world.all_gather_into(&count, &mut counts[..]);
        let starts: Vec<i32> = counts
            .iter()
            .scan(0i32, |start, &c| {
                let here = *start;
                *start = start.saturating_add(c);
                Some(here)
            })
            .collect();
        let total = counts.iter().map(|&c| c as usize).sum();
        let mut all = vec![0.0; total];
        let mut partition = PartitionMut::new(&mut all[..], &counts[..], &starts[..]);
        world.all_gather_varcount_into(mine, &mut partition);
        counts
            .iter()
            .zip(&starts)
            .map(|(&c, &start)| all[start as usize..(start + c) as usize].to_vec())
            .collect()
    }

    fn any(&self, flag: bool) -> bool {
        use mpi::collective::SystemOperation;
        use mpi::traits::CommunicatorCollectives;
        let world = mpi::topology::SimpleCommunicator::world();
        let mut any = 0i32;
        world.all_reduce_into(&i32::from(flag), &mut any, SystemOperation::logical_or());
        any != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::commands::EXIT_INPUT;

    #[test]
    fn a_build_without_mpi_started_as_several_ranks_refuses_with_exit_2() {
        let Err(refusal) = without_mpi(Some(2)) else {
            panic!("two ranks without MPI must refuse");
        };
        assert_eq!(refusal.code, EXIT_INPUT);
        assert!(refusal.error.to_string().contains("--features mpi"));
        for launched in [None, Some(1)] {
            let launch = without_mpi(launched).map_err(|f| f.error.to_string());
            assert!(launch.is_ok_and(|l| l.ranks.is_none()), "{launched:?}");
        }
    }
}
