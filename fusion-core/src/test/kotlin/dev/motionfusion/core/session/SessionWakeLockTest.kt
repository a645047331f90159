package dev.motionfusion.core.session

import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.event.SessionStream
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path

/** meta.json's `wake_lock`: which case of the recording's wake lock applied (docs/SESSION_FORMAT.md). */
class SessionWakeLockTest {
    @TempDir
    lateinit var tmp: Path

    private fun meta(dir: Path) = String(Files.readAllBytes(dir.resolve(SessionMetadata.FILE_NAME)), Charsets.UTF_8)

    @Test
    fun `wake_lock round-trips through writing, closing and recovery, and is absent when not said`() {
        val held = WakeLockUse(true, "not_wake_up", listOf(SessionStream.MAGNETOMETER, SessionStream.GYROSCOPE_UNCALIBRATED))
        val dir = tmp.resolve("held")
        SessionWriter.create(dir, SessionMetadata(source = "test", wakeLock = held)).use { it.gyroscope(10L, 0.1f, 0.2f, 0.3f, 3) }
        SessionReader.open(dir).use { assertEquals(held, it.metadata.wakeLock) }
        assertTrue("\"forced_by\": [\"magnetometer\", \"gyroscope_uncalibrated\"]" in meta(dir).replace(Regex("\\s+"), " "), meta(dir))

        val released = WakeLockUse(false, "hardware_batching")
        val killed = tmp.resolve("killed")
        val w = SessionWriter.create(killed, SessionMetadata(source = "test", wakeLock = released))
        w.gyroscope(10L, 0.1f, 0.2f, 0.3f, 3)
        w.flush()
        w.abandon()
        SessionRecovery.recover(killed)
        SessionReader.open(killed).use { assertEquals(released, it.metadata.wakeLock) }

        val plain = tmp.resolve("plain")
        SessionWriter.create(plain, SessionMetadata(source = "test")).close()
        assertTrue("wake_lock" !in meta(plain))
        SessionReader.open(plain).use { assertNull(it.metadata.wakeLock) }
    }

    @Test
    fun `a stream a newer version knows is left out, a wrong type is an error naming the member`() {
        val dir = tmp.resolve("s")
        SessionWriter.create(dir, SessionMetadata(source = "test", wakeLock = WakeLockUse(true, "not_wake_up", listOf(SessionStream.MAGNETOMETER)))).close()
        val file = dir.resolve(SessionMetadata.FILE_NAME)
        Files.writeString(file, meta(dir).replace("\"magnetometer\"]", "\"magnetometer\", \"heart_rate\"]").replace("\"not_wake_up\"", "\"some_newer_case\""))
        SessionReader.open(dir).use { assertEquals(WakeLockUse(true, "some_newer_case", listOf(SessionStream.MAGNETOMETER)), it.metadata.wakeLock) }
        Files.writeString(file, meta(dir).replace("\"heart_rate\"", "3"))
        val e = assertThrows(DataFormatException::class.java) { SessionReader.open(dir).close() }
        assertTrue("wake_lock.forced_by[1]" in e.message!!, e.message)
    }
}
