package dev.motionfusion.core.input

import dev.motionfusion.core.settings.FilterSettingDescriptors
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.DynamicTest
import org.junit.jupiter.api.TestFactory
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import kotlin.math.abs
import kotlin.math.acos
import kotlin.math.sqrt

/**
 * Inputs that parse but cannot be right (docs/IMPORT.md, "Plausibility"), one generated test per
 * case: each either fails with a message naming what is wrong, or replays to the orientation of
 * the same table without the fault (within 0.5°) with the fault counted as skipped.
 */
class PlausibilityTest {
    @TempDir
    lateinit var tmp: Path

    /** One row of a 100 Hz table of a phone lying flat and turning slowly about z: t, gyroscope, accelerometer, magnetometer (the field turning with it). */
    private class Row(var t: Double, val g: DoubleArray, val a: DoubleArray, val m: DoubleArray)

    private fun rows(n: Int = 2000) = (0 until n).map { i ->
        val turned = 0.2 * i * 0.01
        Row(i * 0.01, doubleArrayOf(0.0, 0.0, 0.2), doubleArrayOf(0.0, 0.0, 9.805), doubleArrayOf(22.0 * kotlin.math.sin(turned), 22.0 * kotlin.math.cos(turned), -40.0))
    }

    private fun write(name: String, rows: List<Row>, mag: Boolean = true): Path {
        val header = "t_s,gx,gy,gz,ax,ay,az" + if (mag) ",mx,my,mz\n" else "\n"
        val text = rows.joinToString("", header) { r ->
            (listOf(r.t) + r.g.toList() + r.a.toList() + if (mag) r.m.toList() else emptyList()).joinToString(",", postfix = "\n") { v -> if (v == Math.rint(v) && abs(v) < 1e15) v.toLong().toString() else v.toString() }
        }
        return tmp.resolve("$name.csv").also { Files.writeString(it, text) }
    }

    /** The last orientation of a replay and the filter's skipped-out-of-range count. */
    private fun replay(p: Path): Pair<DoubleArray, Long> = Recording.open(p).use { rec ->
        val last = DoubleArray(4)
        var nan = 0
        val r = Replayer(FilterSettings())
        rec.events().use { e ->
            r.run(e, rec.originNs, object : ReplayListener {
                override fun step(step: ReplayStep) {
                    if (step.initialised && step.orientation.any { it.isNaN() }) nan++
                    step.orientation.copyInto(last)
                }
            }, source = rec.name)
        }
        assertEquals(0, nan, "rows holding NaN after the start")
        last to r.filter.diagnostics().skippedOutOfRange
    }

    private fun angleDeg(p: DoubleArray, q: DoubleArray) =
        Math.toDegrees(2 * acos(abs(p.indices.sumOf { p[it] * q[it] }).coerceAtMost(1.0)))

    private val clean by lazy { replay(write("clean", rows())).first }

    private fun refused(name: String, message: String, change: (List<Row>) -> List<Row>, mag: Boolean = true) = DynamicTest.dynamicTest("$name: refused") {
        val p = write(name.replace(Regex("[^A-Za-z0-9]"), "-"), change(rows()), mag)
        val e = assertThrows(DataFormatException::class.java) { replay(p) }
        assertTrue(Regex(message).containsMatchIn(e.message!!), "expected /$message/ in: ${e.message}")
    }

    private fun skipped(name: String, change: (List<Row>) -> Unit) = DynamicTest.dynamicTest("$name: skipped, counted, the rest replays as without it") {
        val r = rows()
        change(r)
        val (q, out) = replay(write(name.replace(Regex("[^A-Za-z0-9]"), "-"), r))
        assertEquals(1L, out)
        assertTrue(angleDeg(q, clean) < 0.5, "off by ${angleDeg(q, clean)}°")
    }

    @TestFactory
    fun `time axis`() = listOf(
        refused("t_s in milliseconds", """the timestamps imply 0\.1 Hz: the times look like ms, not s \(that would be 100 Hz\)""", { r -> r.onEach { it.t *= 1000 } }),
        refused("rows in reverse order", """1999 of the first 1999 timestamp steps step back \(rows in reverse order\?\)""", { it.reversed() }),
        refused("all times zero", """timestamp steps are all the same \(0 s\)""", { r -> r.onEach { it.t = 0.0 } }),
        refused("a 1 Hz table", """the timestamps imply 1 Hz""", { r -> r.onEach { it.t *= 100 } }),
        refused("t_s in microseconds", """the times look like µs, not s""", { r -> r.onEach { it.t *= 1e6 } }),
        refused("times going back midway", """gyroscope timestamps step back by 9\.990 s at gyroscope sample 1001 \(from t = 9\.990 s to 0\.000 s, times from the first sample; in a plain table, its data row 1001\): the recording is out of order""", { r -> r.onEachIndexed { i, it -> if (i >= 1000) it.t -= 10.0 } }),
        refused("times stalled after a few rows", """of \d+ gyroscope timestamps do not advance|timestamp steps do not advance""", { r -> r.onEachIndexed { i, it -> if (i >= 10) it.t = 0.1 } }),
    )

    @TestFactory
    fun `impossible values`() = listOf(
        skipped("one accelerometer reading of 1e308") { it[700].a[2] = 1e308 },
        skipped("one accelerometer reading of 3e38") { it[700].a[0] = 3e38 },
        skipped("one gyroscope reading of 1e30") { it[700].g[1] = 1e30 },
        skipped("one magnetometer reading of 1e308") { it[700].m[0] = 1e308 },
        skipped("one gyroscope reading of 200 rad/s") { it[700].g[2] = -200.0 },
        refused("every accelerometer reading beyond range", """accelerometer: median \|a\| 1\.00e\+06 m/s² is over 3 g""", { r -> r.onEach { it.a[2] = 1e6 } }),
        DynamicTest.dynamicTest("most readings beyond range after the probed start: refused") {
            val p = write("late-faults", rows(6000).onEachIndexed { i, it -> if (i >= 2500) it.a[2] = 1e6 })
            val e = assertThrows(DataFormatException::class.java) { replay(p) }
            assertTrue("3500 readings are beyond any phone's range (3500) or not finite (0), over half of a stream's 6000 samples" in e.message!!, e.message)
        },
    )

    @TestFactory
    fun `wrong units`() = listOf(
        refused("accelerometer in g", """accelerometer: looks like g, not m/s² \(median \|a\| 1; .*multiply the accelerometer by 9\.80665""", { r -> r.onEach { for (k in 0..2) it.a[k] /= 9.8 * 1.0004 } }),
        refused("accelerometer in mg", """accelerometer: median \|a\| 1000 m/s² is over 3 g""", { r -> r.onEach { for (k in 0..2) it.a[k] *= 1000 / 9.805 } }),
        refused("gyroscope in degrees per second", """gyroscope: median \|ω\| 11\.5 rad/s: looks like °/s, not rad/s""", { r -> r.onEach { it.g[2] = Math.toDegrees(it.g[2]) } }),
        refused("magnetometer all zero", """magnetometer: is zero throughout: no field was recorded; replay in 6D""", { r -> r.onEach { it.m.fill(0.0) } }),
        refused("magnetometer in gauss", """magnetometer: looks like gauss, not µT""", { r -> r.onEach { for (k in 0..2) it.m[k] /= 100 } }),
        refused("magnetometer in nT", """magnetometer: looks like nT, not µT""", { r -> r.onEach { for (k in 0..2) it.m[k] *= 1000 } }),
    )

    @TestFactory
    fun `settings far outside any meaningful range`() = listOf("beta" to 1e308, "zeta" to 1e9, "maxGap" to 1e6, "accNormTolerance" to 1e4, "gyroSaturation" to 1e12).map { (name, v) ->
        DynamicTest.dynamicTest("$name = $v: refused with the range") {
            val e = assertThrows(IllegalArgumentException::class.java) { FilterSettingDescriptors.named(name)!!.with(FilterSettings(), v) }
            assertTrue(Regex("""$name must be within 0–\d+""").containsMatchIn(e.message!!), e.message)
        }
    }

    @TestFactory
    fun `every descriptor's default lies within its limits`() = FilterSettingDescriptors.all.filter { it.limits != null }.map { d ->
        DynamicTest.dynamicTest(d.name) { assertTrue((d.default as Double?)?.let { it in d.limits!! } ?: d.zeroDisables, "${d.default} outside ${d.limits}") }
    }

    @TestFactory
    fun `plausible tables replay`() = listOf(
        "a clean table" to rows(),
        "a table without magnetometer" to rows(),
        "a 5 Hz table" to rows(200).onEach { it.t *= 20 },
        "a 4 kHz table" to rows(8000).onEach { it.t /= 40 },
    ).mapIndexed { i, (name, r) ->
        DynamicTest.dynamicTest(name) { val (q, out) = replay(write("ok$i", r, mag = i != 1)); assertEquals(0L, out); assertTrue(q.all { it.isFinite() } && abs(sqrt(q.sumOf { it * it }) - 1) < 1e-9) }
    }
}
