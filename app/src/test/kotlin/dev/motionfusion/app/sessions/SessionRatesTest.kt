package dev.motionfusion.app.sessions

import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionWriter
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Rule
import org.junit.Test
import org.junit.rules.TemporaryFolder
import java.io.File

/** Each stream's rate over time, read from a session written by the core session writer. */
class SessionRatesTest {
    @get:Rule
    val tmp = TemporaryFolder()

    /** [seconds] of accelerometer at [accHz] and gyroscope at [gyroHz], the gyroscope silent from [gapFrom] for [gapS] s. */
    private fun session(seconds: Int, accHz: Int, gyroHz: Int, gapFrom: Int = -1, gapS: Int = 0): File {
        val dir = File(tmp.root, "s")
        val meta = SessionMetadata(appVersion = "test", startAnchor = ClockAnchor(1_795_688_100_000L, 0L), filterSettings = FilterSettings())
        val t0 = 5_000_000_000L
        SessionWriter.create(dir.toPath(), meta).use { w ->
            val n = seconds.toLong() * accHz * gyroHz
            // Events in time order: both streams on a common tick of 1 / (accHz · gyroHz) s.
            val tick = 1_000_000_000L / (accHz.toLong() * gyroHz)
            for (k in 0 until n) {
                val t = t0 + k * tick
                if (k % gyroHz == 0L) w.accelerometer(t, 0f, 0f, 9.81f, 3)
                val s = (k * tick / 1_000_000_000L).toInt()
                if (k % accHz == 0L && (s < gapFrom || s >= gapFrom + gapS)) w.gyroscope(t + 1, 0f, 0f, 0f, 3)
            }
            w.close(t0 + seconds * 1_000_000_000L)
        }
        return dir
    }

    @Test
    fun `1-s bins give each stream's events per second, a stall shows as zero`() {
        val r = CoreSessionLibrary.rates(session(30, accHz = 50, gyroHz = 20, gapFrom = 10, gapS = 5), 1200)
        assertEquals(1.0, r.binSeconds, 0.0)
        assertEquals(30, r.bins)
        val acc = r.ratesHz.getValue("accelerometer")
        val gyro = r.ratesHz.getValue("gyroscope")
        for (b in 0 until 30) assertEquals("acc bin $b", 50f, acc[b], 0f)
        for (b in 0 until 30) assertEquals("gyro bin $b", if (b in 10..14) 0f else 20f, gyro[b], 0f)
        assertEquals(listOf("accelerometer", "gyroscope"), r.ratesHz.keys.toList())
    }

    @Test
    fun `an hour in at most the bins asked for, the bin width doubling`() {
        val r = CoreSessionLibrary.rates(session(3600, accHz = 5, gyroHz = 2), 1200)
        assertEquals(4.0, r.binSeconds, 0.0) // 3600 1-s bins > 1200 → 2 s (1800) → 4 s (900)
        assertEquals(900, r.bins)
        assertTrue(r.ratesHz.values.all { it.size <= 1200 })
        assertEquals(5f, r.ratesHz.getValue("accelerometer")[450], 0f)
        assertEquals(2f, r.ratesHz.getValue("gyroscope")[899], 0f)
        // Counts survive the merges: the sum of rate · width is every event.
        assertEquals(3600.0 * 5, r.ratesHz.getValue("accelerometer").sumOf { it * r.binSeconds }, 1e-6)
    }
}
