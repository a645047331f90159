package dev.motionfusion.core.session

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.ByteArrayOutputStream
import java.nio.file.Files
import java.nio.file.Path

/** meta.json's `continues` (a recording resumed after its process was killed) and the zip's progress. */
class SessionContinuationTest {
    @TempDir
    lateinit var tmp: Path

    @Test
    fun `continues round-trips, survives a recovery of the continuing part, and is absent from other sessions`() {
        val c = Continuation("session_2026-11-26_14-03-12", 8_183_456_789_012L, 8_225_456_789_012L)
        assertEquals(42_000_000_000L, c.gapNs)
        val dir = tmp.resolve("part2")
        SessionWriter.create(dir, SessionMetadata(source = "test", continues = c)).use { it.gyroscope(8_225_500_000_000L, 0.1f, 0.2f, 0.3f, 3) }
        SessionReader.open(dir).use { assertEquals(c, it.metadata.continues) }
        val text = String(Files.readAllBytes(dir.resolve(SessionMetadata.FILE_NAME)), Charsets.UTF_8)
        assertTrue("\"gap_start_elapsed_realtime_ns\": 8183456789012" in text, text)

        // Killed again: the recovery of the second part keeps it.
        val killed = tmp.resolve("killed")
        val w = SessionWriter.create(killed, SessionMetadata(source = "test", continues = c.copy(gapStartElapsedRealtimeNs = null)))
        w.gyroscope(10L, 0.1f, 0.2f, 0.3f, 3)
        w.flush()
        w.abandon()
        SessionRecovery.recover(killed)
        SessionReader.open(killed).use {
            assertEquals(c.copy(gapStartElapsedRealtimeNs = null), it.metadata.continues)
            assertNull(it.metadata.continues!!.gapNs)
        }

        // A session that continues nothing has no member.
        val plain = tmp.resolve("plain")
        SessionWriter.create(plain, SessionMetadata(source = "test")).close()
        assertTrue("continues" !in String(Files.readAllBytes(plain.resolve(SessionMetadata.FILE_NAME)), Charsets.UTF_8))
        SessionReader.open(plain).use { assertNull(it.metadata.continues) }
    }

    @Test
    fun `the zip reports its progress to the end, and an exception from it stops the zip`() {
        val dir = tmp.resolve("s")
        SessionWriter.create(dir, SessionMetadata(source = "test")).use { w ->
            for (i in 0 until 50_000) w.accelerometer(i * 5_000_000L, 0.1f, 0.2f, 9.81f, 3)
        }
        val total = listOf("meta.json", "accelerometer.csv").sumOf { Files.size(dir.resolve(it)) }
        val seen = ArrayList<Long>()
        val full = ByteArrayOutputStream()
        SessionArchive.zip(dir, full, 0L) { done, t -> assertEquals(total, t); seen += done }
        assertEquals(0L, seen.first())
        assertEquals(total, seen.last())
        assertTrue(seen.size > total / 65_536)
        assertTrue(seen.zipWithNext().all { (a, b) -> b >= a })

        class Stop : RuntimeException()
        val out = ByteArrayOutputStream()
        assertThrows(Stop::class.java) { SessionArchive.zip(dir, out, 0L) { done, _ -> if (done > 100_000) throw Stop() } }
        assertTrue(out.size() < full.size(), "${out.size()} bytes written of a whole zip's ${full.size()}")
    }
}
