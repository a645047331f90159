package dev.motionfusion.cli

import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionWriter
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Path

/** A session whose meta.json records the live filter's settings replays with them unless told otherwise. */
class RecordedSettingsTest {
    @TempDir
    lateinit var dir: Path

    private fun session(name: String, settings: FilterSettings?): String {
        val d = dir.resolve(name)
        val meta = SessionMetadata(source = "test", startAnchor = ClockAnchor(0L, 1_000_000_000L), filterSettings = settings)
        SessionWriter.create(d, meta).use { w ->
            MotionSimulator(SimulationSettings(seed = 5, rateHz = 100.0, durationS = 8.0, restWindows = listOf(TimeWindow(0.0, 1.0)))).forEach {
                val t = 1_000_000_000L + it.timestampNs
                w.accelerometer(t, it.acc.x.toFloat(), it.acc.y.toFloat(), it.acc.z.toFloat(), 3)
                w.magnetometer(t, it.mag.x.toFloat(), it.mag.y.toFloat(), it.mag.z.toFloat(), 3)
                w.gyroscope(t, it.gyro.x.toFloat(), it.gyro.y.toFloat(), it.gyro.z.toFloat(), 3)
            }
        }
        return d.toString()
    }

    @Test
    fun `replay, plot and compare start from the recorded settings`() {
        val live = FilterSettings(beta = 0.3, headingGain = 0.4, restBiasEstimation = false)
        val recorded = session("recorded", live)
        val r = fusion("replay", recorded)
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue("starting from the live filter's settings in meta.json" in r.err, r.err)
        val defaults = fusion("replay", recorded, "--quiet", "--default-settings").out
        assertNotEquals(defaults, r.out)
        // The same as naming every recorded value that differs from the defaults.
        assertEquals(r.out, fusion("replay", recorded, "--quiet", "--default-settings", "--beta", "0.3", "--set", "headingGain=0.4", "--no-rest-bias").out)
        // Options change the recorded settings, not the defaults.
        assertEquals(
            fusion("replay", recorded, "--quiet", "--default-settings", "--beta", "0.05", "--set", "headingGain=0.4", "--no-rest-bias").out,
            fusion("replay", recorded, "--quiet", "--beta", "0.05").out,
        )
        assertFalse("meta.json" in fusion("replay", recorded, "--quiet").err)

        // A session without recorded settings, and --report, are as before.
        val plain = session("plain", null)
        val p = fusion("replay", plain)
        assertFalse("live filter's settings" in p.err, p.err)
        assertEquals(fusion("replay", plain, "--quiet", "--report").out, fusion("replay", recorded, "--quiet", "--report").out)

        val plot = fusion("plot", recorded, "-o", dir.resolve("p.svg").toString())
        assertEquals(ExitCode.OK, plot.code, plot.err)
        assertTrue("starting from the live filter's settings" in plot.err, plot.err)
    }

    @Test
    fun `--set NAME=off turns a mechanism off as =0 does, and a session recorded with it off replays with it off`() {
        val recorded = session("off", FilterSettings(headingGain = null, gyroSaturation = null))
        // meta.json keeps off as 0, the form every earlier version wrote and reads.
        val meta = java.nio.file.Files.readString(Path.of(recorded, "meta.json"))
        assertTrue(Regex(""""heading_gain_1_s"\s*:\s*0(\.0)?[,}\s]""").containsMatchIn(meta), meta)
        val r = fusion("replay", recorded, "--quiet")
        assertEquals(ExitCode.OK, r.code, r.err)
        assertNotEquals(fusion("replay", recorded, "--quiet", "--default-settings").out, r.out)
        assertEquals(r.out, fusion("replay", recorded, "--quiet", "--default-settings", "--set", "headingGain=off,gyroSaturation=OFF").out)
        assertEquals(r.out, fusion("replay", recorded, "--quiet", "--default-settings", "--set", "headingGain=0,gyroSaturation=0").out)
        // --set once for each setting: both apply (a later --set once silently replaced the earlier).
        assertEquals(r.out, fusion("replay", recorded, "--quiet", "--default-settings", "--set", "headingGain=off", "--set", "gyroSaturation=off").out)
        // On again by a number; a setting that cannot be off refuses "off" in the tool's words.
        assertEquals(fusion("replay", recorded, "--quiet", "--default-settings").out, fusion("replay", recorded, "--quiet", "--set", "headingGain=${FilterSettings().headingGain},gyroSaturation=${FilterSettings().gyroSaturation}").out)
        val bad = fusion("replay", recorded, "--quiet", "--set", "beta=off")
        assertEquals(ExitCode.USAGE, bad.code)
        assertTrue("--set beta: 'off' is not a number" in bad.err, bad.err)
        val typo = fusion("replay", recorded, "--quiet", "--set", "headingGain=of")
        assertTrue("--set headingGain: 'of' is not a number or off" in typo.err, typo.err)
    }
}
