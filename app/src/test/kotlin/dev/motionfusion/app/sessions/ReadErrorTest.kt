package dev.motionfusion.app.sessions

import java.io.File
import java.io.IOException
import java.nio.file.Files
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Test

class ReadErrorTest {
    @Test
    fun `a reader's message names the session's files as inside the session, not by the app's storage path`() {
        val root = Files.createTempDirectory("sessions").toFile()
        try {
            val dir = File(root, "session_2026-11-26_14-03-12")
            val e = IOException("${File(dir, "meta.json").absolutePath}: missing: not a session (no meta.json)")
            val shown = readError(dir, e)
            assertEquals("meta.json: missing: not a session (no meta.json)", shown)
            assertFalse(root.absolutePath in shown)
            // A relative folder as well as an absolute one.
            val rel = File("sessions", "walk")
            assertEquals("gyroscope.csv:12:3: expected a number", readError(rel, IOException("${File(rel, "gyroscope.csv").path}:12:3: expected a number")))
            // No message: the exception's kind.
            assertEquals("IOException", readError(dir, IOException()))
        } finally {
            root.deleteRecursively()
        }
    }
}
