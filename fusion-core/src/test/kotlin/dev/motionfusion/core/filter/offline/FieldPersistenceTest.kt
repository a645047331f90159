package dev.motionfusion.core.filter.offline

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.SimulatedRuns
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.sim.MagneticDisturbance
import dev.motionfusion.core.sim.MagneticDisturbanceKind
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulatedSample
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertThrows
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

    private val threshold = OfflineSettings.BUILDING_PERSISTENCE_DEG

    private fun simulated(disturbances: List<MagneticDisturbance> = emptyList(), rests: List<TimeWindow> = emptyList(), rate: Double = 0.8): List<SimulatedSample> =
        MotionSimulator(
            SimulationSettings(
                seed = 5, rateHz = 100.0, durationS = 180.0, angularRate = rate,
                gyroBias = Vector3(0.0, 0.0, 0.5 * PI / 180.0), magDisturbances = disturbances, restWindows = rests,
            ),
        ).run()

    /**
     * [samples] as a table, each field reading plus [distortion] at its time (world frame, µT), replayed: the
     * persistence, °. With [awkward], the table as phones and exports give it: the magnetometer on one row in four
     * (empty fields on the others), the gyroscope's timestamp repeated every 5 s, and a gap of 2 s at 90 s.
     */
    private fun persistence(
        samples: List<SimulatedSample>, distortion: (Double) -> Vector3, settings: FilterSettings = FilterSettings(), name: String = "t.csv",
        awkward: Boolean = false,
    ): Double {
        val file = dir.resolve(name)
        Files.newBufferedWriter(file).use { w ->
            w.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n")
            var previous = ""
            for ((i, s) in samples.withIndex()) {
                var t = s.timestampNs * 1e-9
                if (awkward && t > 90.0 && t < 92.0) continue
                val m = s.truth.inverseRotate(s.truth.rotate(s.mag) + distortion(t))
                val v = listOf(s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z)
                val time = String.format(Locale.ROOT, "%.6f", t)
                val field = if (awkward && i % 4 != 0) ",,," else listOf(m.x, m.y, m.z).joinToString("") { ",$it" }
                w.write((if (awkward && i % 500 == 0 && previous.isNotEmpty()) previous else time) + v.joinToString("") { ",$it" } + field + "\n")
                previous = time
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
    fun `it judges the field against the gyroscope, not against the filter's heading`() {
        // The filter's heading follows the field closely at a high heading gain and hardly at a low one; the field's
        // departure from the gyroscope is the same either way (a wrong sign on the filter's corrections would not be).
        val samples = simulated()
        val defaults = persistence(samples, building, name = "a.csv")
        val close = persistence(samples, building, FilterSettings(headingGain = 0.5), name = "b.csv")
        val loose = persistence(samples, building, FilterSettings(headingGain = 0.01), name = "c.csv")
        val msg = String.format(Locale.ROOT, "a building at heading gain 0.08 (the default) %.2f°, 0.5 %.2f°, 0.01 %.2f°", defaults, close, loose)
        println(msg)
        assertTrue(kotlin.math.abs(close - defaults) < 0.5 && kotlin.math.abs(loose - defaults) < 0.5, msg)
    }

    @Test
    fun `a slower magnetometer, stalled timestamps and a gap change little`() {
        val samples = simulated()
        val walk = persistence(samples, building, name = "plain.csv")
        val awkwardWalk = persistence(samples, building, name = "awkward.csv", awkward = true)
        val awkwardClean = persistence(samples, none, name = "awkward-clean.csv", awkward = true)
        val msg = String.format(Locale.ROOT, "a building %.2f°, the same table made awkward %.2f°; a clean field made awkward %.2f°", walk, awkwardWalk, awkwardClean)
        println(msg)
        assertTrue(kotlin.math.abs(awkwardWalk - walk) < 1.0 && awkwardWalk > threshold, msg)
        assertTrue(awkwardClean < 2.0, msg)
    }

    /** The offline replay of the table [name] written by [persistence]: its heading RMS against the truth after 20 s, °, and its rows. */
    private fun offline(samples: List<SimulatedSample>, name: String, settings: OfflineSettings): Pair<Double, List<DoubleArray>> {
        val rows = ArrayList<DoubleArray>()
        Recording.open(dir.resolve(name)).use { rec ->
            rec.events().use {
                Replayer().runOffline(it, rec.originNs, object : ReplayListener { override fun step(step: ReplayStep) { rows += step.orientation.copyOf() } }, offline = settings)
            }
        }
        val est = rows.map { Quaternion(it[0], it[1], it[2], it[3]) }
        return SimulatedRuns.rms(est, samples, samples.indexOfFirst { it.timestampNs >= 20_000_000_000L }, metric = SimulatedRuns::headingDeg) to rows
    }

    private val never = OfflineSettings(buildingPersistence = Double.POSITIVE_INFINITY)

    @Test
    fun `offline, a walk that looks like a building learns no bias in motion, any other walk is replayed as before`() {
        // The heading still follows the field, and the heading smoother still learns the bias about the vertical: a
        // gyroscope 0.5°/s off with no rest to learn it from costs nothing (with the magnetic trust instead it did:
        // 30.2° against 4.3°, docs/ACCURACY.md).
        val lines = ArrayList<String>()
        val results = ArrayList<Triple<Double, Double, Double>>()
        for ((label, samples) in listOf(
            "a rest of 10 s, then turning slowly" to simulated(rests = listOf(TimeWindow(0.0, 10.0)), rate = 0.15),
            "no rest, turning slowly" to simulated(rate = 0.15),
            "no rest, turning briskly" to simulated(),
        )) {
            val name = label.replace(Regex("[^a-z]+"), "-") + ".csv"
            val p = persistence(samples, building, name = name)
            val (switched, _) = offline(samples, name, OfflineSettings())
            val (before, _) = offline(samples, name, never)
            lines += String.format(Locale.ROOT, "%s: persistence %.1f°, offline heading RMS %.2f° (learning the bias in motion %.2f°)", label, p, switched, before)
            results += Triple(p, switched, before)
        }
        val msg = lines.joinToString("\n")
        println(msg)
        for ((p, switched, before) in results) {
            assertTrue(p > threshold, msg)
            assertTrue(switched != before && switched < before + 0.1, msg)
        }
        // A clean field: no switch, the same rows.
        val samples = simulated()
        assertTrue(persistence(samples, none, name = "field.csv") < threshold)
        assertSameRows(offline(samples, "field.csv", OfflineSettings()).second, offline(samples, "field.csv", never).second)
    }

    private fun assertSameRows(a: List<DoubleArray>, b: List<DoubleArray>) =
        assertTrue(a.size == b.size && a.indices.all { a[it].contentEquals(b[it]) }, "the rows differ")

    @Test
    fun `the switch's setting is checked`() {
        assertThrows(IllegalArgumentException::class.java) { OfflineSettings(buildingPersistence = 0.0) }
        assertThrows(IllegalArgumentException::class.java) { OfflineSettings(buildingPersistence = Double.NaN) }
    }

    @Test
    fun `no judgement without a magnetometer's heading or before 20 s`() {
        assertTrue(persistence(simulated(), building, FilterSettings(mode = FilterMode.IMU)).isNaN())
        assertTrue(persistence(simulated().filter { it.timestampNs < 15_000_000_000L }, building, name = "short.csv").isNaN())
    }
}
