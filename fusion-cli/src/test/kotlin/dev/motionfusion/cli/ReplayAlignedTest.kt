package dev.motionfusion.cli

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SensorInfo
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionWriter
import dev.motionfusion.core.sync.ClockExchange
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.util.Random
import kotlin.math.abs

/**
 * `fusion replay SESSION… --align METHOD -o DIR/`: the rows of simulated phones whose sensor clocks are seconds apart
 * and drift against each other, put on the first phone's timeline, compared with the truth (docs/SYNC.md).
 */
class ReplayAlignedTest {
    @TempDir
    lateinit var dir: Path

    private fun p(name: String) = dir.resolve(name).toString()

    /** A phone's sensor clock: [baseNs] at the simulation's 0, running [driftPpm] fast against the laptop's (true time). */
    private class Clock(val baseNs: Long, val driftPpm: Double) {
        fun at(trueNs: Long): Long = baseNs + trueNs + Math.round(trueNs * driftPpm * 1e-6)

        /** The true time of phone time [phoneNs] (the inverse of [at] to within a nanosecond). */
        fun trueOf(phoneNs: Long): Double = (phoneNs - baseNs) / (1 + driftPpm * 1e-6)
    }

    /** A session written as a phone with [clock] would have recorded the simulated motion; returns its gyroscope times. */
    private fun session(
        name: String, seed: Int, rate: Int, clock: Clock, anchor: Boolean, link: Boolean, violent: String? = "shake@8,drop@14",
    ): LongArray {
        val raw = p("raw-$name.csv")
        val args = mutableListOf("simulate", "-o", raw, "--duration", "20", "--rate", "$rate", "--seed", "$seed")
        if (violent != null) args += listOf("--violent", violent)
        assertEquals(ExitCode.OK, fusion(*args.toTypedArray()).code)
        val meta = SessionMetadata(
            source = "test phone $name",
            // Both phones' wall clocks read WALL_MS at the simulation's 0, as network time would have them (exactly here).
            startAnchor = if (anchor) ClockAnchor(WALL_MS, clock.at(0)) else null,
            sensors = listOf(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE, SessionStream.MAGNETOMETER).map { SensorInfo(it, "simulated", "test", 1) },
        )
        // Exchanges with one laptop (its clock: true time + 3 s) every 250 ms: up and down 0.3 ms at the shortest plus up to 20 ms of jitter.
        val random = Random(seed.toLong())
        val exchanges = if (!link) emptyList() else (0 until 100).map { k ->
            val t = k * 250_000_000L - 2_000_000_000L
            val up = 300_000L + (random.nextDouble() * 20e6).toLong()
            val down = 300_000L + (random.nextDouble() * 20e6).toLong()
            ClockExchange(LAPTOP_NS + t, clock.at(t + up), clock.at(t + up + 50_000), LAPTOP_NS + t + up + 50_000 + down)
        }
        val times = ArrayList<Long>()
        SessionWriter.create(dir.resolve(name), meta).use { w ->
            var next = 0
            for (line in Files.readAllLines(Path.of(raw)).drop(1)) {
                val v = line.split(',').map { it.toDouble() }
                val t = clock.at(Math.round(v[0] * 1e9))
                while (next < exchanges.size && exchanges[next].t2 <= t) w.clockExchange(exchanges[next++], "laptop-1")
                w.accelerometer(t, v[4].toFloat(), v[5].toFloat(), v[6].toFloat(), 3)
                w.magnetometer(t, v[7].toFloat(), v[8].toFloat(), v[9].toFloat(), 3)
                w.gyroscope(t, v[1].toFloat(), v[2].toFloat(), v[3].toFloat(), 3)
                times += t
            }
            while (next < exchanges.size) w.clockExchange(exchanges[next++], "laptop-1")
        }
        return times.toLongArray()
    }

    /** The t_s column of a replay output. */
    private fun rowTimes(file: String): DoubleArray = Files.readAllLines(Path.of(file)).drop(1).map { it.substringBefore(',').toDouble() }.toDoubleArray()

    /** alignment.csv's row of [input]: method and uncertainty_ns (null: not known). */
    private fun alignment(out: String, input: String): Pair<String, Double?> {
        val lines = Files.readAllLines(Path.of(out, "alignment.csv"))
        assertEquals(Aligner.CSV_HEADER, lines[0])
        val row = lines.single { it.startsWith("$input,") }.split(',')
        return row[1] to row[4].takeIf { it.isNotEmpty() }?.toDouble()
    }

    /**
     * Replays the sessions aligned by [method] and checks every row of each one after the first: its time is the true
     * instant of its gyroscope sample on the first phone's clock, within [bound] ns (null: the stated uncertainty).
     * Returns the largest error per input, ns.
     */
    private fun check(method: String, phones: List<Triple<String, Clock, LongArray>>, expectedMethod: String, bound: Double?, anchored: Boolean = true): List<Double> {
        val out = p("out-$method") + "/"
        val r = fusion("replay", *phones.map { p(it.first) }.toTypedArray(), "--align", method, "-o", out, "--mode", "6d")
        assertEquals(ExitCode.OK, r.code, r.err)
        assertFalse(r.err.contains("Exception"), r.err)
        val (refName, refClock, refGyro) = phones.first()
        // The first phone's own rows are as a replay without --align gives them.
        val alone = fusion("replay", p(refName), "-o", p("alone-$method.csv"), "--mode", "6d")
        assertEquals(ExitCode.OK, alone.code, alone.err)
        assertTrue(rowTimes(p("alone-$method.csv")).contentEquals(rowTimes("$out$refName.csv")))
        // t = 0 s: the first phone's start anchor (taken at the simulation's 0), else its first sample.
        val origin = if (anchored) refClock.at(0) else refGyro[0]
        return phones.drop(1).map { (name, clock, gyro) ->
            val (used, stated) = alignment(out, name)
            assertEquals(expectedMethod, used)
            val limit = bound ?: stated!!
            val rows = rowTimes("$out$name.csv")
            assertEquals(gyro.size, rows.size)
            var worst = 0.0
            for (i in gyro.indices) {
                val truth = (refClock.at(Math.round(clock.trueOf(gyro[i]))) - origin) * 1e-9
                worst = maxOf(worst, abs(rows[i] - truth) * 1e9)
            }
            assertTrue(worst <= limit, "$name by $used: rows up to ${worst / 1e6} ms off the truth, stated ${limit / 1e6} ms")
            val figures = "%.4f ms off the truth, stated %s ms".format(java.util.Locale.ROOT, worst / 1e6, stated?.let { "%.4f".format(java.util.Locale.ROOT, it / 1e6) })
            println("replay --align $method: $name by $used: rows up to $figures")
            assertTrue(r.err.contains("$name on $refName's timeline: $used"), r.err)
            worst
        }
    }

    @Test
    fun `linked sessions are put on the first phone's timeline by their clock exchanges, within the stated uncertainty`() {
        // Seconds apart, drifting −80 and +95 ppm against the laptop: 3.5 ms between them over the 20 s, far beyond the bound.
        val a = Clock(5_000_123_456_789L, -80.0)
        val b = Clock(7_350_987_654_321L, 95.0)
        val c = Clock(912_000_000_000L, 40.0)
        val phones = listOf(
            Triple("a", a, session("a", 8, 200, a, anchor = true, link = true)),
            Triple("b", b, session("b", 9, 100, b, anchor = true, link = true)),
            Triple("c", c, session("c", 10, 50, c, anchor = false, link = true)),
        )
        val worst = check("auto", phones, "link", null)
        // The drift is followed: a constant offset would be off by up to 1.75 ms at the ends.
        assertTrue(worst.all { it < 1_000_000 }, "$worst")
        check("link", phones, "link", null)
    }

    @Test
    fun `sessions with wall-clock anchors only are put on one timeline by them, the uncertainty left open`() {
        val a = Clock(5_000_123_456_789L, 0.0)
        val b = Clock(7_350_987_654_321L, 0.0)
        val phones = listOf(
            Triple("a", a, session("a", 8, 100, a, anchor = true, link = false, violent = null)),
            // A name with a format directive in it, as any file name may have.
            Triple("b%s", b, session("b%s", 9, 100, b, anchor = true, link = false, violent = null)),
        )
        // Independent motions: the gyroscopes cannot tell, the wall clocks decide (their anchors here exact to the ns).
        check("utc", phones, "utc", 1_000.0)
        val worst = check("auto", phones, "utc", 1_000.0)
        assertTrue(worst.single() <= 1_000.0)
        assertEquals(null, alignment(p("out-auto/"), "b%s").second)
    }

    @Test
    fun `a shared shake puts sessions without anchors on one timeline within one sample period`() {
        val a = Clock(5_000_123_456_789L, 20.0)
        val b = Clock(5_002_400_000_000L, -25.0)
        val phones = listOf(
            Triple("a", a, session("a", 8, 200, a, anchor = false, link = false)),
            Triple("b", b, session("b", 9, 100, b, anchor = false, link = false)),
        )
        val worst = check("auto", phones, "gyro", null, anchored = false)
        // The bound: the slower phone's sample period (100 Hz on its own clock, 25 ppm slow).
        assertEquals(10_000_000.0, alignment(p("out-auto/"), "b").second!!, 10_000.0)
        check("gyro", phones, "gyro", null, anchored = false)
        assertTrue(worst.single() < 10_000_000)
    }

    @Test
    fun `recordings that cannot be aligned, and one recording alone, are refused with a message and nothing written`() {
        val a = Clock(5_000_123_456_789L, 0.0)
        val b = Clock(5_001_200_000_000L, 0.0)
        session("a", 8, 100, a, anchor = false, link = false, violent = null)
        session("b", 9, 100, b, anchor = false, link = false, violent = null)
        session("u", 10, 100, b, anchor = true, link = false, violent = null)
        // No clock exchanges, no wall clocks, independent motions.
        val none = fusion("replay", p("a"), p("b"), "--align", "auto", "-o", p("out") + "/")
        assertEquals(ExitCode.DATA_ERROR, none.code, none.err)
        assertTrue(none.err.contains("b: cannot be put on a's timeline") && none.err.contains("shared motion"), none.err)
        assertFalse(none.err.contains("Exception") || none.err.contains("\tat "), none.err)
        assertFalse(Files.exists(Path.of(p("out"))))
        val link = fusion("replay", p("a"), p("u"), "--align", "link", "-o", p("out") + "/")
        assertEquals(ExitCode.DATA_ERROR, link.code, link.err)
        assertTrue(link.err.contains("no clock exchanges with the same laptop"), link.err)
        val utc = fusion("replay", p("a"), p("u"), "--align", "utc", "-o", p("out") + "/")
        assertEquals(ExitCode.DATA_ERROR, utc.code, utc.err)
        assertTrue(utc.err.contains("no wall-clock anchor"), utc.err)
        assertFalse(Files.exists(Path.of(p("out"))))
        // Usage: one input, a method that is none, --max-lag alone, an input named like the alignment file.
        for (args in listOf(
            listOf("replay", p("a"), "--align", "auto", "-o", p("out") + "/"),
            listOf("replay", p("a"), "--align", "auto"),
            listOf("replay", p("a"), p("b"), "--align", "ntp", "-o", p("out") + "/"),
            listOf("replay", p("a"), p("b"), "--max-lag", "3", "-o", p("out") + "/"),
        )) {
            val r = fusion(*args.toTypedArray())
            assertEquals(ExitCode.USAGE, r.code, "$args: ${r.err}")
            assertTrue(r.err.contains("--align") || r.err.contains("--max-lag"), r.err)
        }
        val clash = fusion("replay", p("a"), p("alignment"), "--align", "auto", "-o", p("out") + "/")
        assertEquals(ExitCode.USAGE, clash.code, clash.err)
        assertTrue(clash.err.contains("where --align writes the alignment"), clash.err)
        assertFalse(Files.exists(Path.of(p("out"))))
    }

    private companion object {
        const val WALL_MS = 1_764_158_400_000L
        const val LAPTOP_NS = 3_000_000_000L
    }
}
