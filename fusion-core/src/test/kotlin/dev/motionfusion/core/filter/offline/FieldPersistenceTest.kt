package dev.motionfusion.core.filter.offline

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.sim.MagneticDisturbance
import dev.motionfusion.core.sim.MagneticDisturbanceKind
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulatedSample
import dev.motionfusion.core.sim.SimulationSettings
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.util.Locale
import kotlin.math.PI
import kotlin.math.sin

/**
 * Replayer.fieldPersistenceDeg on a simulated phone turned about for three minutes, its gyroscope off by a steady
 * 0.5°/s: a field whose errors come and go within seconds (noise, magnets passing) stays under the building
 * threshold, a field distorted along a walk, changing over tens of seconds, goes over it.
 */
class FieldPersistenceTest {
    @TempDir
    lateinit var dir: Path

    private val threshold = Replayer.BUILDING_FIELD_PERSISTENCE_DEG

    private fun simulated(disturbances: List<MagneticDisturbance> = emptyList()): List<SimulatedSample> =
        MotionSimulator(
            SimulationSettings(
                seed = 5, rateHz = 100.0, durationS = 180.0, angularRate = 0.8,
                gyroBias = Vector3(0.0, 0.0, 0.5 * PI / 180.0), magDisturbances = disturbances,
            ),
        ).run()

    /** [samples] as a table, each field reading plus [distortion] at its time (world frame, µT), replayed: the persistence, °. */
    private fun persistence(samples: List<SimulatedSample>, distortion: (Double) -> Vector3, settings: FilterSettings = FilterSettings(), name: String = "t.csv"): Double {
        val file = dir.resolve(name)
        Files.newBufferedWriter(file).use { w ->
            w.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n")
            for (s in samples) {
                val t = s.timestampNs * 1e-9
                val m = s.truth.inverseRotate(s.truth.rotate(s.mag) + distortion(t))
                val v = listOf(s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z, m.x, m.y, m.z)
                w.write(String.format(Locale.ROOT, "%.6f", t) + v.joinToString("") { "," + it } + "\n")
            }
        }
        val replayer = Replayer(settings)
        Recording.open(file).use { rec ->
            rec.events().use { replayer.run(it, rec.originNs, object : ReplayListener { override fun step(step: ReplayStep) {} }) }
        }
        return replayer.fieldPersistenceDeg
    }

    private val none: (Double) -> Vector3 = { Vector3.ZERO }

    /** A walk through a building: up to 12 µT added, changing over 17–31 s, as the steel around the path changes. */
    private val building: (Double) -> Vector3 = { t -> Vector3(12.0 * sin(2 * PI * t / 23.0), 12.0 * sin(2 * PI * t / 31.0), 8.0 * sin(2 * PI * t / 17.0)) }

    @Test
    fun `a clean field, magnets passing and a building`() {
        val clean = persistence(simulated(), none, name = "clean.csv")
        val passes = persistence(simulated((0 until 6).map { MagneticDisturbance(MagneticDisturbanceKind.FERROUS_PASS, 25.0 + 25.0 * it, 4.0) }), none, name = "passes.csv")
        val walk = persistence(simulated(), building, name = "building.csv")
        val msg = String.format(Locale.ROOT, "median persistence: clean %.1f°, six magnets passing %.1f°, a building %.1f° (threshold %.1f°)", clean, passes, walk, threshold)
        println(msg)
        assertTrue(clean < 2.0, msg)
        assertTrue(passes < threshold, msg)
        assertTrue(walk > threshold, msg)
    }

    @Test
    fun `no judgement without a magnetometer's heading or before 20 s`() {
        assertTrue(persistence(simulated(), building, FilterSettings(mode = FilterMode.IMU)).isNaN())
        assertTrue(persistence(simulated().filter { it.timestampNs < 15_000_000_000L }, building, name = "short.csv").isNaN())
    }
}
