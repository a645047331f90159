// Android Studio project (Gradle). The build of record is the Maven reactor (pom.xml); these files
// describe the same modules, folders, dependencies and versions, and AndroidStudioProjectTest (app)
// fails when the two differ. They are not run by CI here: no Gradle distribution or Android Gradle
// Plugin is reachable from the build machines.
pluginManagement {
    repositories {
        google()
        mavenCentral()
        gradlePluginPortal()
    }
}

dependencyResolutionManagement {
    repositoriesMode.set(RepositoriesMode.FAIL_ON_PROJECT_REPOS)
    repositories {
        google()
        mavenCentral()
    }
}

rootProject.name = "motion-fusion"

// fusion-bench (JMH) depends on the app module's recording classes, which Gradle does not offer to
// a JVM module: run it with Maven. android-libs and android-test-libs are the Maven build's way of
// resolving AARs; Gradle resolves them itself from the app's dependencies.
include(":fusion-core")
include(":fusion-cli")
include(":app")
