package dev.motionfusion.app.record

import android.content.Context
import android.util.Log
import java.io.File

/** Finds sessions a killed process or a storage failure left unfinished and repairs them. */
internal object InterruptedSessions {
    /** Recovers every interrupted session except the one being recorded; returns the recovered folders. */
    fun recoverAll(context: Context, format: SessionFormat = RecordingDeps.format): List<File> {
        val recording = (RecordingStatus.state as? RecordingStatus.State.Active)?.session
        val recovered = ArrayList<File>()
        for (dir in SessionFolders.list(context)) {
            if (dir == recording) continue
            try {
                if (format.isInterrupted(dir)) {
                    format.recover(dir)
                    recovered += dir
                }
            } catch (e: Exception) {
                Log.w("InterruptedSessions", "cannot recover ${dir.name}: ${e.message}")
            }
        }
        return recovered
    }
}
