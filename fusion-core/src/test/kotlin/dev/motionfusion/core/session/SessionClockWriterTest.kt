package dev.motionfusion.core.session

import dev.motionfusion.core.sync.ClockExchange
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path

/** clock.csv through the one session writer (the app's recordings and fusion listen), and meta.json's remote_start. */
class SessionClockWriterTest {
    @TempDir
    lateinit var tmp: Path

    @Test
    fun `the first exchange names the link, another laptop's are not written, the reader gets them back`() {
        val dir = tmp.resolve("s")
        val start = RemoteStart("fusion record on lab", "lab boot 1", 1_000_000_000L, 6_000_000_000L)
        val exchanges = listOf(ClockExchange(1, 5_000_000_100L, 5_000_000_200L, 400), ClockExchange(250_000_001, 5_250_000_100L, 5_250_000_150L, 250_000_300))
        SessionWriter.create(dir, SessionMetadata(startAnchor = ClockAnchor(1_764_000_000_000L, 5_000_000_000L), remoteStart = start)).use { w ->
            w.gyroscope(6_000_000_000L, 0.1f, 0.2f, 0.3f, 3)
            assertTrue(w.clockExchange(exchanges[0], "lab boot 1"))
            // meta.json names the link as soon as the first exchange is written (a killed recording keeps it).
            assertEquals("lab boot 1", SessionReader.open(dir).use { it.metadata.clockLink })
            assertFalse(w.clockExchange(ClockExchange(7, 5_000_000_300L, 5_000_000_400L, 900), "other laptop boot 2"))
            assertTrue(w.clockExchange(exchanges[1], "lab boot 1"))
        }
        SessionReader.open(dir).use { r ->
            assertEquals("lab boot 1", r.metadata.clockLink)
            assertEquals(exchanges, r.clockExchanges())
            assertEquals(start, r.metadata.remoteStart)
        }
        assertEquals(SessionClock.HEADER, Files.readAllLines(dir.resolve(SessionClock.FILE_NAME))[0])
    }
}
